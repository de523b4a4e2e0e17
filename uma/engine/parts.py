"""The engine's parts, built from its configuration and ladder (`UmaEngine` dispatches to them).

Units: times in seconds, sizes in bits.
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.codecs import Role, model_names, names, spec
from uma.config.scenario import EngineConfig, FeedbackConfig
from uma.engine.description import Delivery
from uma.engine.inflight import Keyframes
from uma.engine.ladder import Ladder
from uma.engine.model import ModelMachine
from uma.engine.points import OperatingPoint
from uma.engine.policy import POLICIES, SWITCHING, switch_settings
from uma.engine.position import Position
from uma.engine.rate import RateControl, make_rate
from uma.engine.records import Tally
from uma.engine.refresh import RefreshPlanner
from uma.engine.sending import Outbox
from uma.engine.sendside import SendSide
from uma.engine.switching import Switcher

__all__ = ["DescriptionPlan", "EngineParts", "build_parts"]


@dataclass(frozen=True)
class DescriptionPlan:
    """The content description to deliver: `bits` in `chunks` packets of `chunk_bits` each
    (0 bits: nothing to deliver, or the receiver is assumed to hold it)."""

    bits: int = 0
    chunks: int = 0
    chunk_bits: int = 0


@dataclass(frozen=True)
class EngineParts:
    """Each part owns its state; `declared` are the counts a run reports even at 0."""

    ladder: Ladder
    model: ModelMachine
    model_config: object  # the model codec's config section
    description: Delivery
    switcher: Switcher
    refresh: RefreshPlanner | None
    outbox: Outbox
    keyframes: Keyframes
    position: Position
    sender: SendSide
    rate: RateControl
    declared: tuple[Tally, ...]


def build_parts(
    config: EngineConfig,
    points: tuple[OperatingPoint, ...],
    *,
    source_fps: float,
    model_unavailable: str,
    coverage: tuple[tuple[float, str], ...],
    description: DescriptionPlan,
    feedback: FeedbackConfig,
    payload_bytes: int,
    keyframe_min_interval_s: float,
) -> EngineParts:
    """The parts of an engine on `points`."""
    ladder = Ladder(points, codec=config.codec, source_fps=source_fps)
    model_name = ladder.model_codec or model_names()[0]
    model_config = getattr(config, spec(model_name).config_section)
    if ladder.model_point is None and not model_unavailable:
        model_unavailable = f"no {model_name} operating point on the ladder"
    model = ModelMachine(
        model_name,
        unavailable=model_unavailable,
        retry_s=config.switching.retry_ms / 1000.0,
        ladder_label=spec(config.codec).label,
    )
    declared = model.declared()
    declared += [Tally(f"{spec(name).config_section}_failures", 0) for name in names(Role.REGION)]
    delivery = Delivery(
        bits=description.bits, chunks=description.chunks, chunk_bits=description.chunk_bits,
        share=model_config.description_share, codec=model_name,
    )  # fmt: skip
    switcher = Switcher(
        SWITCHING[config.switching.policy],
        switch_settings(config, ladder=config.codec, model=model_name),
        ladder=ladder, model=model, description=delivery, coverage=coverage,
    )  # fmt: skip
    refresh = _refresh(model_config)
    declared += [Tally(key, 0) for key in RefreshPlanner.COUNTS] if refresh else []
    declared += [Tally("skipped_frames", 0), Tally("probes", 0)]
    outbox = Outbox(config.pacer, payload_bytes=payload_bytes, source_fps=source_fps)
    keyframes = Keyframes(keyframe_min_interval_s)
    floor_kbps = 0.0  # the send gates judge by no less than the lowest skippable rung
    if config.rung_floor:
        skippable = [p.rate_kbps for p in points if spec(p.codec).skip_for_backlog]
        floor_kbps = min(skippable, default=0.0)
    rate = make_rate(config, feedback, floor_kbps=floor_kbps)
    position = Position(
        config, points, ladder=ladder, switcher=switcher, policy=POLICIES[config.policy],
        rung=ladder.initial(config, rate.state.estimate_kbps),
    )  # fmt: skip
    sender = SendSide(
        config, points, outbox=outbox, refresh=refresh, source_fps=source_fps, pads=rate.pads
    )
    return EngineParts(
        ladder, model, model_config, delivery, switcher, refresh, outbox, keyframes,
        position, sender, rate, tuple(declared),
    )  # fmt: skip


def _refresh(model_config) -> RefreshPlanner | None:
    """The refresh's planner when the model codec's section enables it."""
    refresh = getattr(model_config, "refresh", None)
    return RefreshPlanner(refresh) if refresh is not None and refresh.enabled else None
