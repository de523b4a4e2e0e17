"""The SimPy processes of one run: sender, engine, receiver reports and display.

Units: simulation time in seconds; logs in ms, kbit/s and bits as their column names say.
Each process is a plain generator function over a shared `World` (built by `uma.sim.world`). The
codec work is real (libx264 and FFmpeg's decoder through PyAV; the model-based codec's tracker
and parameter coder); the time it would take a real engine is modelled from the operating
point (`engine.transcode_ms` for H.264; MBC's cost per fitting-cost evaluation), never read
from the wall clock. The MBC initialisation runs as its own process (a second core of the
engine), so frames keep flowing as H.264 until it is done.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import simpy

from uma.config.scenario import Scenario
from uma.engine.engine import EngineEvent, UmaEngine
from uma.metrics.framelog import FrameLog
from uma.sim.capacity import CapacitySchedule
from uma.sim.links import Downlink, FixedLink, LinkProps, deliver_later
from uma.sim.packets import (
    HEADER_BYTES,
    EncodedUnit,
    Packet,
    packet_sizes_bits,
    packetize,
    padding_packets,
    padding_sizes_bits,
)
from uma.sim.receiver import ReceiverState

__all__ = [
    "World",
    "sender_process",
    "engine_process",
    "mbc_init_process",
    "report_process",
    "display_process",
]


@dataclass
class World:
    """Everything the processes share; wired by `uma.sim.world.build_world`."""

    env: simpy.Environment
    scenario: Scenario
    frames: int
    fps: float
    source_iter: Any
    ladder: Any
    engine: UmaEngine
    capacity: CapacitySchedule
    uplink: FixedLink
    downlink: Downlink
    receiver: ReceiverState
    link_props: Callable[[str], LinkProps]
    feedback_rng: np.random.Generator
    log: FrameLog
    codec: Any  # uma.sim.codecs.CodecChain: the real encoders and decoders
    quality: Any  # uma.sim.quality.QualityMeter
    progress: Callable[[int, int], None] | None = None
    source_frames: dict[int, np.ndarray] = field(default_factory=dict)
    inbox: simpy.Store | None = None
    next_unit_seq: int = 0
    feedback_lost: int = 0
    on_display: Callable | None = None  # (index, source, shown, picture): `uma report --video`
    faults: Any = None  # uma.sim.faults.Faults: feedback silence
    playout: Any = None  # uma.sim.playout: FixedPlayout or AdaptivePlayout (None: fixed)
    padding_bits: int = 0
    points: tuple = ()  # the engine's operating points
    init_us_per_evaluation: float = 0.0
    mbc_init_frames: list[int] = field(default_factory=list)  # where initialisations started
    # Each initialisation's frame and fitted parameters (None when it failed), for its MDE.
    mbc_inits: list[tuple[int, Any]] = field(default_factory=list)
    description_chunks: int = 0  # packets the content description takes
    face_boxes: list = field(default_factory=list)  # per source frame read: `uma.face.Box` | None
    engine_mbc_compute_s: float = 0.0  # modelled: MBC tracking, coding, initialisations
    description_next: int = 0
    description_credit_bits: float = 0.0
    description_sent_bits: int = 0

    def mbc_init_compute_s(self, evaluations: int) -> float:
        """Modelled seconds of one MBC initialisation that cost `evaluations`."""
        return self.init_us_per_evaluation * evaluations / 1e6

    def send_feedback(self, item, handler: Callable) -> None:
        """Carry a report or request over the mobile uplink; lost in an outage or at random."""
        now_s = self.env.now
        silent = self.faults is not None and self.faults.feedback_silent(now_s)
        if silent or self.capacity.rate_kbps_at(now_s) <= 0.0:
            self.feedback_lost += 1
            return
        props = self.link_props(self.capacity.technology_at(now_s))
        if self.feedback_rng.random() < props.loss_rate:
            self.feedback_lost += 1
            return
        deliver_later(self.env, props.delay_s, lambda value: handler(value, self.env.now), item)


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
        mbc_data = world.codec.sender_encode_mbc(frame, index)
        size_bits = encoded.size_bits + (8 * len(mbc_data) if mbc_data else 0)
        world.uplink.send(size_bits, (index, encoded, mbc_data), world.inbox.put)


def engine_process(env: simpy.Environment, world: World):
    """Decode the sender's stream, let the engine decide, transcode and queue on the downlink."""
    engine = world.engine
    scenario = world.scenario
    oracle = scenario.engine.policy == "oracle"
    switching = scenario.engine.switching
    lookahead_s = switching.oracle_lookahead_ms / 1000.0 if switching.policy == "oracle" else None
    log = world.log
    while True:
        index, encoded, mbc_data = yield world.inbox.get()
        picture = world.codec.engine_decode(encoded)
        world.codec.engine_receive_mbc(mbc_data, index)
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
        log["estimate_kbps"][index] = engine.estimate_kbps
        log["rung"][index] = decision.rung
        log["scheduled"][index] = int(decision.scheduled)
        if decision.init_mbc:
            if picture is None:
                engine.on_init_done(False, env.now, reason="no decoded picture to start from")
            else:
                world.mbc_init_frames.append(index)
                env.process(mbc_init_process(env, world, picture, index))
        if engine.description_pending:
            _send_description(world, decision.point, capacity_kbps)
        if not decision.send or picture is None:
            continue
        point = decision.point
        if world.codec.engine_point not in (-1, decision.rung):
            leftover = world.codec.engine_flush()  # MBC's open packet, when leaving MBC
            if leftover is not None and leftover.data:
                _send(world, leftover, world.points[world.codec.engine_point], index)
        out = world.codec.engine_encode(
            picture, decision.rung, force_idr=decision.force_idr, frame=index
        )
        if decision.force_idr and out.keyframe:
            engine.on_keyframe_sent(env.now)
        compute_s = point.compute_s(out.evaluations)
        if (out.reinitialised or out.failure) and point.codec == "mbc":
            # The tracker lost the face and initialised again: that work costs as an init.
            compute_s = point.compute_s(0) + world.mbc_init_compute_s(out.evaluations)
        if out.reinitialised:
            engine.events.append(EngineEvent(env.now, "mbc_reinit", f"frame {index}"))
        if out.failure:
            engine.on_track_failed(out.failure, env.now)
        if point.codec == "mbc":
            world.engine_mbc_compute_s += compute_s
        yield env.timeout(compute_s)
        if not out.failure:
            # A frame MBC buffers for its next packet is sent; its bits count with the packet.
            log["codec"][index] = point.codec
            log["width"][index] = out.width
            log["height"][index] = out.height
            log["sent"][index] = 1
        if out.data:
            _send(world, out, point, index)


def _send_description(world: World, point, capacity_kbps: float) -> None:
    """Send chunks of the content description with the room the budget leaves.

    The budget is the policy's (safety x estimate; x the true capacity for the oracle). Each
    frame interval earns the larger of (budget - the point's rate) and
    `engine.mbc.description_share` x budget of credit (the top rung leaves no room), the whole
    budget while MBC waits for the description; chunks go out while the credit lasts and,
    unless MBC waits, the downlink is not backlogged, round and round the description until a
    receiver report says it is complete (a lost chunk comes again).
    """
    engine = world.engine
    scenario = world.scenario
    payload_bytes = scenario.downlink.packet_bytes
    # The budget as the policy sees it: safety x estimate (x the true capacity for the oracle).
    seen_kbps = capacity_kbps if scenario.engine.policy == "oracle" else engine.estimate_kbps
    budget_kbps = scenario.engine.safety * seen_kbps
    waiting = engine.description_wait_from_s is not None
    if waiting:
        credit_kbps = budget_kbps  # MBC is wanted and waits for it: all the budget
    else:
        credit_kbps = max(
            budget_kbps - point.rate_kbps, scenario.engine.mbc.description_share * budget_kbps
        )
    world.description_credit_bits += credit_kbps * 1000.0 / world.fps
    chunks = world.description_chunks
    budget_bits = engine.estimate_kbps * scenario.engine.max_backlog_ms / 2.0
    size_bits = 8 * (payload_bytes + HEADER_BYTES)
    while world.description_credit_bits >= size_bits and (
        waiting or engine.outstanding_bits < budget_bits
    ):
        chunk = world.description_next % chunks
        world.description_next += 1
        world.description_credit_bits -= size_bits
        seq = engine.on_packets_sent([size_bits])
        world.downlink.offer(
            Packet(
                seq=seq,
                unit=None,
                index=chunk,
                count=chunks,
                size_bits=size_bits,
                sent_s=world.env.now,
                chunk=chunk,
            )
        )
        world.description_sent_bits += size_bits


def _send(world: World, out, point, index: int) -> None:
    """Put one coded unit on the downlink (and the probe or WebRTC padding behind it)."""
    engine = world.engine
    scenario = world.scenario
    payload_bytes = scenario.downlink.packet_bytes
    frames = out.frames or (index,)
    unit = EncodedUnit(
        unit_seq=world.next_unit_seq,
        frame=frames[-1],
        codec=point.codec,
        rung=world.points.index(point),
        width=out.width,
        height=out.height,
        keyframe=out.keyframe,
        data=out.data,
        frames=out.frames,
    )
    world.next_unit_seq += 1
    first_seq = engine.on_packets_sent(packet_sizes_bits(unit, payload_bytes=payload_bytes))
    for packet in packetize(
        unit, first_seq=first_seq, payload_bytes=payload_bytes, sent_s=world.env.now
    ):
        world.downlink.offer(packet)
    if scenario.engine.estimator.kind == "webrtc":
        _pad_to_estimate(world, unit, point, payload_bytes, frames=len(frames))
    elif (
        point.codec == "mbc"
        and scenario.engine.mbc.probe
        and scenario.engine.policy != "oracle"
        and engine.estimator.queue_delay_ms <= scenario.engine.estimator.queue_low_ms
    ):
        # On MBC the parameters alone (a few kbit/s) would cap the estimate at 3 x that:
        # padding lets it find the bandwidth to return (the oracle needs no probe). Only up
        # to safety x the estimate, no further than the rate that would bring the engine back
        # to H.264, and only while the last report saw no queue: padding shares the
        # bottleneck's queue with the parameters, and padding into a queue (the estimate
        # overshot, or the link just got slower) delays them behind it and overflows it.
        limit_kbps = min(
            scenario.engine.switching.to_h264_above_kbps / scenario.engine.safety,
            scenario.engine.safety * engine.estimate_kbps,
        )
        _pad_to_estimate(
            world, unit, point, payload_bytes, frames=len(frames), limit_kbps=limit_kbps
        )
    world.log["keyframe"][frames[0]] = int(unit.keyframe)
    world.log["size_bits"][frames[-1]] = 8 * len(unit.data)


def mbc_init_process(env: simpy.Environment, world: World, picture: np.ndarray, frame: int):
    """Initialise the model-based codec on `picture`; done after its modelled compute time."""
    engine = world.engine
    result = world.codec.mbc_initialise(picture, engine.mbc_point, frame=frame)
    world.mbc_inits.append((frame, result.params if result else None))
    compute_s = world.mbc_init_compute_s(result.evaluations)
    world.engine_mbc_compute_s += compute_s
    yield env.timeout(compute_s)
    engine.on_init_done(bool(result), env.now, reason=result.reason, evaluations=result.evaluations)


def _pad_to_estimate(
    world: World,
    unit: EncodedUnit,
    point,
    payload_bytes: int,
    *,
    frames: int = 1,
    limit_kbps: float = float("inf"),
) -> None:
    """Follow a frame with padding up to the estimate's share of the frame interval.

    A WebRTC sender encodes at its target rate; uma's ladder sends at most a rung's rate, and
    WebRTC's estimator never rises above 1.5 x what it receives, so without this it could never
    climb to the next rung. The padding stands in for the rate a WebRTC encoder would send.
    """
    engine = world.engine
    interval_s = frames / min(point.fps, world.fps)
    sent_bits = sum(packet_sizes_bits(unit, payload_bytes=payload_bytes))
    sizes = padding_sizes_bits(
        min(engine.estimate_kbps, limit_kbps) * 1000.0 * interval_s - sent_bits,
        payload_bytes=payload_bytes,
    )
    if not sizes:
        return
    first_seq = engine.on_packets_sent(sizes)
    for packet in padding_packets(sizes, first_seq=first_seq, sent_s=world.env.now):
        world.downlink.offer(packet)
    world.padding_bits += sum(sizes)


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
