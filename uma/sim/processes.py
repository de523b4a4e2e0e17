"""The SimPy processes of one run: sender, engine, receiver reports and display.

Units: simulation time in seconds; logs in ms, kbit/s and bits as their column names say.
Each process is a plain generator function over a shared `World` (`uma.sim.state`). The engine
process only carries out what the engine decides (`uma.engine.decisions`): it codes the frame
at the point decided, sends the description's chunks and the padding the engine asks for, and
reports outcomes back. The codec work is real (through `uma.sim.codecs`); the time it would
take a real engine is modelled from the operating point, never read from the wall clock. A
model codec's initialisation runs as its own process (a second core of the engine), so frames
keep flowing on the rate ladder until it is done.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import simpy

from uma.sim.packets import (
    EncodedUnit,
    Packet,
    packet_sizes_bits,
    packetize,
    padding_packets,
    padding_sizes_bits,
)
from uma.sim.state import World

__all__ = [
    "World",
    "sender_process",
    "engine_process",
    "init_process",
    "pacer_process",
    "report_process",
    "display_process",
]


def sender_process(env: simpy.Environment, world: World):
    """Capture each frame at its time, encode it at the sender's rate, send it up the good link."""
    for index in range(world.frames):
        capture_s = index / world.fps
        if env.now < capture_s:
            yield env.timeout(capture_s - env.now)
        frame = next(world.source_iter)
        world.source_frames[index] = frame
        world.log["capture_ms"][index] = capture_s * 1000.0
        encoded = world.codec.sender_encode(frame)
        # Selection: the sender's own parameter packet rides with the frame (None otherwise).
        side_data = world.codec.sender_side_data(frame, index)
        size_bits = encoded.size_bits + (8 * len(side_data) if side_data else 0)
        world.uplink.send(size_bits, (index, encoded, side_data), world.inbox.put)


def engine_process(env: simpy.Environment, world: World):
    """Decode the sender's stream, let the engine decide, carry out what it decided."""
    engine = world.engine
    scenario = world.scenario
    oracle = scenario.engine.policy == "oracle"
    switching = scenario.engine.switching
    lookahead_s = switching.oracle_lookahead_ms / 1000.0 if switching.policy == "oracle" else None
    log = world.log
    while True:
        index, encoded, side_data = yield world.inbox.get()
        picture = world.codec.engine_decode(encoded)
        world.codec.engine_receive_side(side_data, index)
        capacity_kbps = world.capacity.rate_kbps_at(env.now)
        decision = engine.on_frame(
            index,
            env.now,
            capacity_kbps=capacity_kbps if oracle else None,
            capacity_ahead_kbps=None
            if lookahead_s is None
            else world.capacity.min_rate_kbps(env.now, env.now + lookahead_s),
        )
        log["technology"][index] = world.capacity.technology_at(env.now)
        log["capacity_kbps"][index] = capacity_kbps
        log["estimate_kbps"][index] = decision.estimate_kbps
        log["queue_bytes"][index] = world.downlink.queued_bytes
        log["engine_queue_bytes"][index] = decision.queued_bits // 8
        log["rung"][index] = decision.rung
        log["scheduled"][index] = int(decision.scheduled)
        if decision.initialise is not None:
            if picture is None:
                engine.on_init_done(False, env.now, reason="no decoded picture to start from")
            else:
                world.init_frames.append(index)
                env.process(init_process(env, world, picture, decision.initialise, index))
        for chunk in decision.description:
            world.downlink.offer(
                Packet(
                    seq=chunk.seq,
                    unit=None,
                    index=chunk.chunk,
                    count=chunk.count,
                    size_bits=chunk.size_bits,
                    sent_s=env.now,
                    chunk=chunk.chunk,
                )
            )
            world.description_sent_bits += chunk.size_bits
        if decision.refresh_adopted is not None:
            world.codec.engine_adopt_refresh(decision.refresh_adopted)
        if not decision.send or picture is None:
            _release_refresh(world)
            continue
        point = decision.point
        if world.codec.engine_point not in (-1, decision.rung):
            leftover = world.codec.engine_flush()  # a buffering encoder's open packet
            if leftover is not None and leftover.data:
                _send(world, leftover, world.codec.engine_point, index)
        out = world.codec.engine_encode(
            picture, decision.rung, force_idr=decision.force_idr, frame=index
        )
        if decision.force_idr and out.keyframe:
            engine.on_keyframe_sent(env.now)
        compute_s = world.compute_s(point, out)
        engine.on_coded(
            index, env.now, rung=decision.rung, reinitialised=out.reinitialised, failure=out.failure
        )
        if decision.refresh is not None and not out.failure:
            compute_s += _code_refresh(world, picture, decision, index)
        yield env.timeout(compute_s)
        if not out.failure:
            # A frame a buffering encoder holds for its next packet is sent; its bits count
            # with the packet.
            log["codec"][index] = point.codec
            log["width"][index] = out.width
            log["height"][index] = out.height
            log["sent"][index] = 1
        if out.data:
            _send(world, out, decision.rung, index)
        _release_refresh(world)


def _code_refresh(world: World, picture: np.ndarray, decision, index: int) -> float:
    """Code the model-aided refresh the engine ordered and queue it in the engine (or tell
    the engine it is not sent); returns its modelled compute seconds (`encode_ms`: coding it,
    decoding it again and judging it against the mirror)."""
    coded = world.codec.engine_refresh(picture, decision.refresh)
    config = world.codec.refresh.config
    world.refresh_compute_s += config.encode_ms / 1000.0
    if coded is None:  # not worth sending: the engine is told so
        world.engine.on_refresh_coded([], world.env.now, intra=False)
        return config.encode_ms / 1000.0
    data, intra = coded
    height, width = picture.shape[0] * 2 // 3, picture.shape[1]
    unit = EncodedUnit(
        unit_seq=world.next_refresh_seq, frame=index, codec=decision.codec, rung=decision.rung,
        width=width, height=height, keyframe=intra, data=data, refresh=True,
    )  # fmt: skip
    world.next_refresh_seq += 1
    packets = packetize(unit, first_seq=-1, payload_bytes=config.packet_bytes, sent_s=world.env.now)
    world.engine.on_refresh_coded(
        [(packet, packet.size_bits) for packet in packets], world.env.now, intra=intra
    )
    return config.encode_ms / 1000.0


def _release_refresh(world: World) -> None:
    """Offer the downlink the refresh packets the engine lets out now."""
    now_s = world.env.now
    for packet, seq in world.engine.on_refresh_pace(now_s):
        world.downlink.offer(replace(packet, seq=seq, sent_s=now_s))
        world.refresh_bits += packet.size_bits


def _send(world: World, out, rung: int, index: int) -> None:
    """Put one coded unit of point `rung` on the downlink, and the padding the engine wants."""
    payload_bytes = world.scenario.downlink.packet_bytes
    frames = out.frames or (index,)
    unit = EncodedUnit(
        unit_seq=world.next_unit_seq,
        frame=frames[-1],
        codec=world.points[rung].codec,
        rung=rung,
        width=out.width,
        height=out.height,
        keyframe=out.keyframe,
        data=out.data,
        frames=out.frames,
    )
    world.next_unit_seq += 1
    sizes = packet_sizes_bits(unit, payload_bytes=payload_bytes)
    paced = world.scenario.engine.pacer.enabled
    if paced:
        # Numbered and stamped when the pacer lets them out.
        packets = packetize(unit, first_seq=-1, payload_bytes=payload_bytes, sent_s=world.env.now)
        sent = world.engine.on_unit_queued(
            [(packet, packet.size_bits) for packet in packets],
            rung=rung,
            frames=frames,
            keyframe=unit.keyframe,
            now_s=world.env.now,
        )
    else:
        sent = world.engine.on_unit_sent(sizes, rung=rung, frames=len(frames))
        for packet in packetize(
            unit, first_seq=sent.first_seq, payload_bytes=payload_bytes, sent_s=world.env.now
        ):
            world.downlink.offer(packet)
    if sent.padding_bits is not None:
        padding = padding_sizes_bits(sent.padding_bits, payload_bytes=payload_bytes)
        if padding and paced:
            packets = padding_packets(padding, first_seq=-1, sent_s=world.env.now)
            world.engine.on_padding_queued(
                [(packet, packet.size_bits) for packet in packets], world.env.now
            )
        elif padding:
            first_seq = world.engine.on_packets_sent(padding)
            for packet in padding_packets(padding, first_seq=first_seq, sent_s=world.env.now):
                world.downlink.offer(packet)
            world.padding_bits += sum(padding)
    world.log["keyframe"][frames[0]] = int(unit.keyframe)
    world.log["size_bits"][frames[-1]] = 8 * len(unit.data)
    if paced:
        world.kick_pacer()


def pacer_process(env: simpy.Environment, world: World):
    """Let out what the engine's pacer releases, when it says, or when something is queued."""
    oracle = world.scenario.engine.policy == "oracle"
    while True:
        decision = world.engine.on_pace(
            env.now, capacity_kbps=world.capacity.rate_kbps_at(env.now) if oracle else None
        )
        for packet, seq in decision.sent:
            world.downlink.offer(replace(packet, seq=seq, sent_s=env.now))
        world.pacer_kick = env.event()
        if math.isinf(decision.next_s):
            yield world.pacer_kick
        else:
            yield world.pacer_kick | env.timeout(decision.next_s - env.now)
        world.pacer_kick = None


def init_process(env: simpy.Environment, world: World, picture: np.ndarray, rung: int, frame: int):
    """Initialise the model codec of point `rung` on `picture`; done after its modelled time."""
    result = world.codec.initialise_model(picture, rung, frame=frame)
    world.inits.append((frame, result.params if result else None))
    compute_s = world.init_compute_s(result.evaluations)
    world.model_compute_s += compute_s
    yield env.timeout(compute_s)
    world.engine.on_init_done(
        bool(result), env.now, reason=result.reason, evaluations=result.evaluations
    )


def report_process(env: simpy.Environment, world: World):
    """Every `feedback.interval_ms`, the receiver reports to the engine."""
    interval_s = world.scenario.feedback.interval_ms / 1000.0
    while True:
        yield env.timeout(interval_s)
        report = world.receiver.make_report(interval_s)
        world.send_feedback(report, world.engine.on_report)


def display_process(env: simpy.Environment, world: World):
    """At each frame's deadline show the newest decoded frame, and score it against the source."""
    playout_s = world.scenario.receiver.playout_delay_ms / 1000.0
    log = world.log
    last_scheduled = -1
    for index in range(world.frames):
        delay_s = playout_s if world.playout is None else world.playout.delay_s(env.now)
        deadline_s = max(env.now, index / world.fps + delay_s)
        if env.now < deadline_s:
            yield env.timeout(deadline_s - env.now)
        if log["scheduled"][index]:
            last_scheduled = index
        shown, picture = world.receiver.shown_at(index)
        log["display_ms"][index] = deadline_s * 1000.0
        log["shown_frame"][index] = shown
        log["frozen"][index] = int(shown < 0 or shown != last_scheduled)
        if shown >= 0:
            log["shown_codec"][index] = log["codec"][shown]
        source = world.source_frames.pop(index)
        if world.on_display is not None:
            world.on_display(index, source, shown, picture)
        box = world.face_boxes[index] if index < len(world.face_boxes) else None
        world.quality.submit(index, source, shown, picture, box=box)
        if world.progress is not None:
            world.progress(index + 1, world.frames)
