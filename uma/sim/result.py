"""What a run leaves behind for metrics and reports, collected from its world once it ends.

Units: times in seconds, rates in kbit/s, sizes in bits or bytes as the names say.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from uma.config.scenario import Scenario
from uma.engine.decisions import EngineEvent, EngineOutcome
from uma.metrics.framelog import FrameLog
from uma.sim.capacity import CapacitySchedule
from uma.sim.links import LinkStats
from uma.sim.playout_replay import DecodedFrame
from uma.sim.stats import DescriptionStats, ModelStats, RefreshStats, SentBits

__all__ = ["RunResult", "collect_result"]


@dataclass(frozen=True)
class RunResult:
    """What a run leaves behind for metrics and reports."""

    scenario: Scenario
    log: FrameLog
    events: tuple[EngineEvent, ...]
    link: LinkStats
    capacity: CapacitySchedule
    duration_s: float
    fps: float
    source_name: str
    width: int
    height: int
    feedback_lost: int
    codec_s: float = 0.0
    metrics_s: float = 0.0
    points: tuple = ()  # the engine's operating points (`uma.engine.points.OperatingPoint`)
    engine_counts: dict | None = None  # MBC inits, failures, refusals (`UmaEngine.counts`)
    codec_seconds: dict | None = None  # with `account`: wall-clock codec seconds per codec
    sent: SentBits = field(default_factory=SentBits)  # bits offered by kind, headers included
    model: ModelStats = field(default_factory=ModelStats)
    description: DescriptionStats = field(default_factory=DescriptionStats)
    refresh: RefreshStats = field(default_factory=RefreshStats)
    face_boxes: tuple = ()  # the face box (`uma.face.Box` or None) of each source frame read
    # Every picture the receiver could show, in decode order: a playout replay's input
    # (`uma.sim.playout_replay`).
    decoded: tuple[DecodedFrame, ...] = ()


def collect_result(
    world,
    outcome: EngineOutcome,
    *,
    events: tuple[EngineEvent, ...],
    source,
    description,
    description_bytes: int,
    duration_s: float,
) -> RunResult:
    """The `RunResult` of the finished run in `world` (`uma.sim.state.World`), whose engine
    left `outcome`."""
    codec = world.codec
    sender = codec.sender.tracker
    return RunResult(
        scenario=world.scenario,
        log=world.log,
        events=events,
        link=world.downlink.stats,
        capacity=world.capacity,
        duration_s=duration_s,
        fps=world.fps,
        source_name=source.name,
        width=source.width,
        height=source.height,
        feedback_lost=world.feedback_lost,
        codec_s=codec.seconds,
        metrics_s=world.quality.seconds,
        sent=replace(world.sent),  # a copy: the result is frozen
        points=world.points,
        engine_counts=dict(outcome.counts),
        codec_seconds=dict(codec.codec_seconds),
        model=ModelStats(
            init_frames=tuple(world.model.init_frames),
            inits=tuple(world.model.inits),
            engine_compute_s=world.model.compute_s,
            sender_bits=sender.bits if sender is not None else 0,
            sender_compute_ms=sender.compute_ms if sender is not None else 0.0,
        ),
        description=DescriptionStats(
            content=description,
            size_bytes=description_bytes,
            sent_bits=world.sent.description,
            delivered_s=world.receiver.description_done_s,
            acked_s=outcome.description_acked_s,
            wait_s=outcome.description_wait_s,
        ),
        refresh=RefreshStats(
            bits=world.sent.refresh,
            compute_s=world.model.refresh_compute_s,
            decoded=world.receiver.refresh_received.decoded,
            lost=world.receiver.refresh_received.lost,
        ),
        face_boxes=tuple(world.face_boxes),
        decoded=_decoded_frames(world),
    )


def _decoded_frames(world) -> tuple[DecodedFrame, ...]:
    """The receiver's decoded pictures in decode order, with the capture instants the playout
    was told (`uma.sim.world` tells it the logged capture time)."""
    capture_ms = world.log["capture_ms"]
    return tuple(
        DecodedFrame(frame, float(capture_ms[frame]) / 1000.0, decode_s, told)
        for frame, decode_s, told in world.receiver.decoded_log
    )
