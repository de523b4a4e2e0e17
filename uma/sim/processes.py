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

import numpy as np
import simpy

from uma.engine.decisions import (
    AdoptRefresh,
    CodedReport,
    DiscardRefresh,
    Initialise,
    OutgoingUnit,
    RefreshCoded,
    SendPacket,
    WakePacer,
)
from uma.sim.packets import EncodedUnit, Packet
from uma.sim.playout import FixedPlayout
from uma.sim.playout_replay import DisplayRule
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
    """Decode the sender's stream, ask the engine, carry out what it returns. A frame takes
    at most three calls: the decision, what coding it came to, and the unit once coded."""
    engine = world.engine
    while True:
        index, encoded, side_data = yield world.inbox.get()
        picture = world.codec.engine_decode(encoded)
        world.codec.engine_receive_side(side_data, index)
        now_s = env.now
        capacity_kbps = world.capacity.rate_kbps_at(now_s)
        decision = engine.on_frame(
            index, now_s, decoded=picture is not None, capacity_kbps=capacity_kbps,
            lowest_kbps=world.capacity.min_rate_kbps,
        )  # fmt: skip
        _log_decision(world, index, decision, capacity_kbps)
        carry_out(world, decision.actions, picture)
        if not decision.send or picture is None:
            continue
        report, unit, compute_s = _code(world, picture, decision, index)
        actions = engine.on_coded(report, env.now)
        if report.refresh is not None and not any(isinstance(a, DiscardRefresh) for a in actions):
            world.next_refresh_seq += 1
        carry_out(world, actions)
        yield env.timeout(compute_s)
        carry_out(world, engine.on_sent(unit, env.now))


def _log_decision(world: World, index: int, decision, capacity_kbps: float) -> None:
    log = world.log
    log["technology"][index] = world.capacity.technology_at(world.env.now)
    log["capacity_kbps"][index] = capacity_kbps
    log["estimate_kbps"][index] = decision.estimate_kbps
    log["queue_bytes"][index] = world.downlink.queued_bytes
    log["engine_queue_bytes"][index] = decision.queued_bits // 8
    log["rung"][index] = decision.rung
    log["scheduled"][index] = int(decision.scheduled)


def carry_out(world: World, actions, picture: np.ndarray | None = None) -> None:
    """Do what the engine returned: offer its packets, start an initialisation on
    `picture`, keep the refresh coder's mirror in step, wake the pacer."""
    env = world.env
    for action in actions:
        if isinstance(action, SendPacket):
            chunk = action.index if action.kind == "description" else -1
            world.downlink.offer(
                Packet(
                    action.seq,
                    action.payload,
                    action.index,
                    action.count,
                    action.size_bits,
                    env.now,
                    chunk,
                )  # fmt: skip
            )
            world.sent.add(action.kind, action.size_bits)
            if action.kind == "video" and action.index == action.count - 1:
                world.codec.engine_released(action.payload)
        elif isinstance(action, Initialise):
            world.model.init_frames.append(action.frame)
            env.process(init_process(env, world, picture, action.rung, action.frame))
        elif isinstance(action, AdoptRefresh):
            world.codec.engine_adopt_refresh(action.frame)
        elif isinstance(action, DiscardRefresh):
            world.codec.engine_discard_refresh(action.frame)
        elif isinstance(action, WakePacer):
            world.kick_pacer()


def _code(world: World, picture: np.ndarray, decision, index: int):
    """Code the frame as decided (and the refresh ordered with it): the report for the
    engine, the unit to send once coded (None: nothing), and the modelled compute seconds."""
    codec, leftover = world.codec, None
    if codec.engine_point not in (-1, decision.rung):
        rest = codec.engine_flush()  # a buffering encoder's open packet
        if rest is not None and rest.data:
            leftover = _unit(world, rest, codec.engine_point, index)
    out = codec.engine_encode(picture, decision.rung, force_idr=decision.keyframe, frame=index)
    compute_s = world.compute_s(decision.point, out)
    refresh = None
    if decision.refresh is not None and not out.failure:
        compute_s += codec.refresh.config.encode_ms / 1000.0
        refresh = _code_refresh(world, picture, decision, index)
    if not out.failure:
        # A frame a buffering encoder holds for its next packet is sent; its bits count
        # with the packet.
        for key, value in (("codec", decision.codec), ("width", out.width),
                           ("height", out.height), ("sent", 1)):  # fmt: skip
            world.log[key][index] = value
    report = CodedReport(
        index, decision.rung, out.keyframe, out.reinitialised, out.failure, leftover, refresh
    )
    return report, _unit(world, out, decision.rung, index) if out.data else None, compute_s


def _code_refresh(world: World, picture: np.ndarray, decision, index: int):
    """Code the model-aided refresh the engine ordered: what it came to (None: no pose)."""
    world.model.refresh_compute_s += world.codec.refresh.config.encode_ms / 1000.0
    coded = world.codec.engine_refresh(picture, decision.refresh)
    if coded is None:
        return None
    data, intra, gain_db = coded
    height, width = picture.shape[0] * 2 // 3, picture.shape[1]
    unit = EncodedUnit(
        unit_seq=world.next_refresh_seq, frame=index, codec=decision.codec, rung=decision.rung,
        width=width, height=height, keyframe=intra, data=data, refresh=True,
    )  # fmt: skip
    return RefreshCoded(index, unit, len(data), intra, gain_db)


def _unit(world: World, out, rung: int, index: int) -> OutgoingUnit:
    """One coded unit of point `rung`, numbered among the units, for the engine to send."""
    frames = out.frames or (index,)
    unit = EncodedUnit(
        unit_seq=world.next_unit_seq, frame=frames[-1], codec=world.points[rung].codec,
        rung=rung, width=out.width, height=out.height, keyframe=out.keyframe, data=out.data,
        frames=out.frames,
    )  # fmt: skip
    world.next_unit_seq += 1
    world.log["keyframe"][frames[0]] = int(unit.keyframe)
    world.log["size_bits"][frames[-1]] = 8 * len(unit.data)
    return OutgoingUnit(unit, len(unit.data), rung, frames, unit.keyframe)


def pacer_process(env: simpy.Environment, world: World):
    """Let out what the engine's pacer releases, when it says, or when something is queued."""
    while True:
        decision = world.engine.on_pace(env.now, capacity_kbps=world.capacity.rate_kbps_at(env.now))
        carry_out(world, decision.sent)
        world.pacer_kick = env.event()
        if math.isinf(decision.next_s):
            yield world.pacer_kick
        else:
            yield world.pacer_kick | env.timeout(decision.next_s - env.now)
        world.pacer_kick = None


def init_process(env: simpy.Environment, world: World, picture: np.ndarray, rung: int, frame: int):
    """Initialise the model codec of point `rung` on `picture`; done after its modelled time."""
    result = world.codec.initialise_model(picture, rung, frame=frame)
    world.model.inits.append((frame, result.params if result else None))
    compute_s = world.init_compute_s(result.evaluations)
    world.model.compute_s += compute_s
    yield env.timeout(compute_s)
    carry_out(
        world,
        world.engine.on_init_done(
            bool(result), env.now, reason=result.reason, evaluations=result.evaluations
        ),
    )


def report_process(env: simpy.Environment, world: World):
    """Every `feedback.interval_ms`, the receiver reports to the engine."""
    interval_s = world.scenario.feedback.interval_ms / 1000.0
    while True:
        yield env.timeout(interval_s)
        report = world.receiver.make_report(interval_s)
        world.send_feedback(
            report, lambda got, now_s: carry_out(world, world.engine.on_report(got, now_s))
        )


def display_process(env: simpy.Environment, world: World):
    """At each frame's deadline show the newest decoded frame, and score it against the source
    (the rule: `uma.sim.playout_replay.DisplayRule`, which a playout replay runs too)."""
    playout = world.playout
    if playout is None:
        playout = FixedPlayout(world.scenario.receiver.playout_delay_ms / 1000.0)
    rule = DisplayRule(playout, world.fps)
    log, receiver = world.log, world.receiver
    for index in range(world.frames):
        deadline_s = rule.deadline_s(index, env.now, world.capacity.technology_at(env.now))
        if env.now < deadline_s:
            yield env.timeout(deadline_s - env.now)
        shown, frozen = rule.show(index, receiver.decoded, bool(log["scheduled"][index]))
        picture = receiver.decoded[shown] if shown >= 0 else None
        log["display_ms"][index] = deadline_s * 1000.0
        log["shown_frame"][index] = shown
        log["frozen"][index] = int(frozen)
        if shown >= 0:
            log["shown_codec"][index] = log["codec"][shown]
        source = world.source_frames.pop(index)
        if world.on_display is not None:
            world.on_display(index, source, shown, picture)
        box = world.face_boxes[index] if index < len(world.face_boxes) else None
        world.quality.submit(index, source, shown, picture, box=box)
        if world.progress is not None:
            world.progress(index + 1, world.frames)
