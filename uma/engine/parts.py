"""The engine's parts, built from its configuration and ladder (`UmaEngine` dispatches to them).

Units: times in seconds, sizes in bits.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from uma.codecs import Role, model_names, names, spec
from uma.config.scenario import EngineConfig
from uma.engine.description import Delivery
from uma.engine.ladder import Ladder
from uma.engine.model import ModelMachine
from uma.engine.points import OperatingPoint
from uma.engine.policy import SWITCHING, switch_settings
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
    ladder: Ladder
    model: ModelMachine
    model_config: object  # the model codec's config section
    description: Delivery
    switcher: Switcher
    counts: dict[str, int]


def build_parts(
    config: EngineConfig,
    points: tuple[OperatingPoint, ...],
    *,
    source_fps: float,
    model_unavailable: str,
    coverage: tuple[tuple[float, str], ...],
    description: DescriptionPlan,
    emit: Callable[[float, str, str], None],
) -> EngineParts:
    """The parts of an engine on `points`; they report events through `emit`."""
    ladder = Ladder(points, codec=config.codec, source_fps=source_fps)
    model_name = ladder.model_codec or model_names()[0]
    model_config = getattr(config, spec(model_name).config_section)
    if ladder.model_point is None and not model_unavailable:
        model_unavailable = f"no {model_name} operating point on the ladder"
    counts: dict[str, int] = {}
    model = ModelMachine(
        model_name,
        unavailable=model_unavailable,
        retry_s=config.switching.retry_ms / 1000.0,
        ladder_label=spec(config.codec).label,
        emit=emit,
        counts=counts,
    )
    for name in names(Role.REGION):
        counts[f"{spec(name).config_section}_failures"] = 0
    delivery = Delivery(
        bits=description.bits,
        chunks=description.chunks,
        chunk_bits=description.chunk_bits,
        share=model_config.description_share,
        codec=model_name,
        emit=emit,
    )
    switcher = Switcher(
        SWITCHING[config.switching.policy],
        switch_settings(config, ladder=config.codec, model=model_name),
        ladder=ladder,
        model=model,
        description=delivery,
        coverage=coverage,
    )
    return EngineParts(ladder, model, model_config, delivery, switcher, counts)
