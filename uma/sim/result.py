"""What a run leaves behind for metrics and reports, collected from its world once it ends.

Units: times in seconds, rates in kbit/s, sizes in bits or bytes as the names say.
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.config.scenario import Scenario
from uma.engine.decisions import EngineEvent, EngineOutcome
from uma.metrics.framelog import FrameLog
from uma.sim.capacity import CapacitySchedule
from uma.sim.links import LinkStats

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
    padding_bits: int = 0
    points: tuple = ()  # the engine's operating points (`uma.engine.points.OperatingPoint`)
    engine_counts: dict | None = None  # MBC inits, failures, refusals (`UmaEngine.counts`)
    codec_seconds: dict | None = None  # with `account`: wall-clock codec seconds per codec
    model_init_frames: tuple[int, ...] = ()  # frames the model codec's initialisations began
    model_inits: tuple = ()  # (frame, fitted parameters or None) of each initialisation
    engine_model_compute_s: float = 0.0  # modelled engine compute for it (inits included)
    sender_model_bits: int = 0  # selection: parameter bits the sender sent up
    sender_model_compute_ms: float = 0.0  # selection: the sender's modelled tracking compute
    description_bytes: int = 0  # the content description delivered to the receiver
    description_sent_bits: int = 0  # on the wire, headers and repeats included
    description_delivered_s: float | None = None  # when its last chunk reached the receiver
    description_acked_s: float | None = None  # when a report told the engine
    description_wait_s: float = 0.0  # time MBC was wanted but the description not there
    description: object = None  # the content description MBC used, if any
    face_boxes: tuple = ()  # the face box (`uma.face.Box` or None) of each source frame read
    refresh_bits: int = 0  # the model-aided refresh on the wire, headers included
    refresh_compute_s: float = 0.0  # its modelled engine compute
    refresh_decoded: int = 0  # refreshes the receiver decoded
    refresh_lost: int = 0  # refreshes the receiver saw lost or could not decode


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
        padding_bits=world.padding_bits,
        points=world.points,
        engine_counts=dict(outcome.counts),
        codec_seconds=dict(codec.codec_seconds),
        model_init_frames=tuple(world.init_frames),
        model_inits=tuple(world.inits),
        engine_model_compute_s=world.model_compute_s,
        sender_model_bits=sender.bits if sender is not None else 0,
        sender_model_compute_ms=sender.compute_ms if sender is not None else 0.0,
        description_bytes=description_bytes,
        description_sent_bits=world.description_sent_bits,
        description_delivered_s=world.receiver.description_done_s,
        description_acked_s=outcome.description_acked_s,
        description_wait_s=outcome.description_wait_s,
        description=description,
        face_boxes=tuple(world.face_boxes),
        refresh_bits=world.refresh_bits,
        refresh_compute_s=world.refresh_compute_s,
        refresh_decoded=world.receiver.refresh_decoded,
        refresh_lost=world.receiver.refresh_lost,
    )
