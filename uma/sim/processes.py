"""The SimPy processes of one run: sender, engine, receiver reports and display.

Units: simulation time in seconds; logs in ms, kbit/s and bits as their column names say.
Each process is a plain generator function over a shared `World` (built by `uma.sim.world`). The
codec work is real (libx264 and FFmpeg's decoder through PyAV); the time it would take a real
engine is modelled (`engine.transcode_ms`), never read from the wall clock.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import simpy

from uma.config.scenario import Scenario
from uma.engine.engine import UmaEngine
from uma.metrics.framelog import FrameLog
from uma.sim.capacity import CapacitySchedule
from uma.sim.links import Downlink, FixedLink, LinkProps, deliver_later
from uma.sim.packets import (
    EncodedUnit,
    packet_sizes_bits,
    packetize,
    padding_packets,
    padding_sizes_bits,
)
from uma.sim.receiver import ReceiverState

__all__ = ["World", "sender_process", "engine_process", "report_process", "display_process"]


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
        world.uplink.send(encoded.size_bits, (index, encoded), world.inbox.put)


def engine_process(env: simpy.Environment, world: World):
    """Decode the sender's stream, let the engine decide, transcode and queue on the downlink."""
    engine = world.engine
    scenario = world.scenario
    oracle = scenario.engine.policy == "oracle"
    transcode_s = scenario.engine.transcode_ms / 1000.0
    payload_bytes = scenario.downlink.packet_bytes
    pad = scenario.engine.estimator.kind == "webrtc"
    log = world.log
    while True:
        index, encoded = yield world.inbox.get()
        picture = world.codec.engine_decode(encoded)
        capacity_kbps = world.capacity.rate_kbps_at(env.now)
        decision = engine.on_frame(index, env.now, capacity_kbps=capacity_kbps if oracle else None)
        log["technology"][index] = world.capacity.technology_at(env.now)
        log["capacity_kbps"][index] = capacity_kbps
        log["estimate_kbps"][index] = engine.estimate_kbps
        log["rung"][index] = decision.rung
        log["scheduled"][index] = int(decision.scheduled)
        if not decision.send or picture is None:
            continue
        width, height = world.codec.rung_size(decision.rung)
        out = world.codec.engine_encode(picture, decision.rung, force_idr=decision.force_idr)
        yield env.timeout(transcode_s)
        unit = EncodedUnit(
            unit_seq=world.next_unit_seq,
            frame=index,
            codec="h264",
            rung=decision.rung,
            width=width,
            height=height,
            keyframe=bool(out.is_keyframe),
            data=out.data,
        )
        world.next_unit_seq += 1
        first_seq = engine.on_packets_sent(packet_sizes_bits(unit, payload_bytes=payload_bytes))
        for packet in packetize(
            unit, first_seq=first_seq, payload_bytes=payload_bytes, sent_s=env.now
        ):
            world.downlink.offer(packet)
        if pad:
            _pad_to_estimate(world, unit, decision.rung, payload_bytes)
        log["codec"][index] = "h264"
        log["width"][index] = width
        log["height"][index] = height
        log["sent"][index] = 1
        log["keyframe"][index] = int(unit.keyframe)
        log["size_bits"][index] = 8 * len(unit.data)


def _pad_to_estimate(world: World, unit: EncodedUnit, rung: int, payload_bytes: int) -> None:
    """Follow a frame with padding up to the estimate's share of the frame interval.

    A WebRTC sender encodes at its target rate; uma's ladder sends at most a rung's rate, and
    WebRTC's estimator never rises above 1.5 x what it receives, so without this it could never
    climb to the next rung. The padding stands in for the rate a WebRTC encoder would send.
    """
    engine = world.engine
    interval_s = 1.0 / min(world.ladder.rungs[rung].fps, world.fps)
    sent_bits = sum(packet_sizes_bits(unit, payload_bytes=payload_bytes))
    sizes = padding_sizes_bits(
        engine.estimate_kbps * 1000.0 * interval_s - sent_bits, payload_bytes=payload_bytes
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
        source = world.source_frames.pop(index)
        if world.on_display is not None:
            world.on_display(index, source, shown, picture)
        world.quality.submit(index, source, shown, picture)
        if world.progress is not None:
            world.progress(index + 1, world.frames)
