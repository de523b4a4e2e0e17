"""The engine's ladder of one run: each codec's operating-point builder, and the model codec's
content description.

Units: rates in kbit/s, frame rates in frames/s, sizes in pixels.

The ladder is, lowest first, the model codec's point (when the run has a content description
for it), the region codec's rungs (when its config section enables them) and the full-frame
codec's rungs (`engine.codec`, from its ladder file). Each role has its builder (`BUILDERS`): a
full-frame codec's points come from its ladder alone, a region or model codec's from its own
config section (`uma.codecs.CodecSpec.config_section`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from uma.codecs import Role, names, spec
from uma.config.scenario import Scenario
from uma.engine.points import OperatingPoint, full_frame_points

__all__ = [
    "BUILDERS",
    "operating_points",
    "ladder_path",
    "load_run_ladder",
    "model_description",
    "ModelPlan",
    "model_plan",
    "ladder_points",
    "region_points",
    "model_point",
]


def ladder_path(scenario: Scenario) -> str:
    """The full-frame codec's ladder file: `engine.ladder`, or the codec's own."""
    from uma.paths import codecs_dir

    if scenario.engine.ladder is not None:
        return scenario.engine.ladder
    return str(codecs_dir() / spec(scenario.engine.codec).ladder)


def load_run_ladder(scenario: Scenario):
    """The full-frame codec's ladder (`uma.video.Ladder`), checked to be that codec's."""
    from uma.errors import ConfigError
    from uma.video import load_ladder

    path = ladder_path(scenario)
    ladder = load_ladder(path)
    found = getattr(ladder, "codec", scenario.engine.codec)  # a ladder file's `codec:`
    if found != scenario.engine.codec:
        raise ConfigError(
            f"engine.ladder: expected a ladder of engine.codec {scenario.engine.codec!r}, "
            f"got {path} of codec {found!r}"
        )
    return ladder


def model_description(scenario: Scenario, source) -> tuple[object | None, str]:
    """The content description the model codec needs, or None and why there is none.

    Only a scenario that switches needs one: the model codec's config section's
    `description` (a `uma describe` file, or a points file the description is fitted from),
    else the source's own (the talking head's astronaut). Without one the engine stays on the
    rate ladder and records why when a switch is due.
    """
    if scenario.engine.switching.policy == "none":
        return None, "switching off"
    section = spec(names(Role.MODEL)[0]).config_section
    path = getattr(scenario.engine, section).description
    if path is not None:
        if path.lower().endswith((".yaml", ".yml", ".json")):  # a points file naming its picture
            from uma.mbc.profile import describe_clip_with_ring  # with its sender's head ring

            return describe_clip_with_ring(path), ""
        from uma.face import load_description

        return load_description(path), ""
    own = getattr(source, "description", None)
    if own is not None:
        return own, ""
    return None, f"no content description (engine.{section}.description) for this source"


@dataclass(frozen=True)
class ModelPlan:
    """The model codec's part of a run: its content description (None: the run has none, and
    `unavailable` says why), the bytes of it to deliver to the receiver (0: none, or the
    receiver is assumed to hold it) and the modelled cost of an initialisation."""

    description: object | None
    unavailable: str
    description_bytes: int
    init_us_per_evaluation: float


def model_plan(scenario: Scenario, source) -> ModelPlan:
    """The `ModelPlan` of `scenario` for `source`."""
    description, unavailable = model_description(scenario, source)
    config = getattr(scenario.engine, spec(names(Role.MODEL)[0]).config_section)
    size = 0
    if description is not None and config.deliver_description:
        size = len(description.to_bytes())
    return ModelPlan(description, unavailable, size, config.init_us_per_evaluation)


def region_points(codec: str, scenario: Scenario, ladder, source) -> tuple[OperatingPoint, ...]:
    """The face-region rungs (`engine.face_region`, when enabled), below the full-frame ones."""
    from uma.errors import ConfigError
    from uma.sim.face_region import detect_pixels

    section = spec(codec).config_section
    config = getattr(scenario.engine, section)
    if not config.enabled:
        return ()
    lowest_kbps = min(rung.rate_kbps for rung in ladder.rungs)
    points = []
    for i, rung in enumerate(config.rungs):
        where = f"engine.{section}.rungs[{i}]"
        if rung.rate_kbps >= lowest_kbps:
            raise ConfigError(
                f"{where}.rate_kbps: expected below the lowest full-frame rung's "
                f"{lowest_kbps:g} kbit/s, got {rung.rate_kbps:g}"
            )
        if rung.width > source.width or rung.height > source.height:
            raise ConfigError(
                f"{where}: expected a coded size within the source's {source.width}x"
                f"{source.height}, got {rung.width}x{rung.height}"
            )
        points.append(
            OperatingPoint(
                codec=codec,
                rate_kbps=rung.rate_kbps,
                fps=min(rung.fps, float(source.fps)),
                width=rung.width,
                height=rung.height,
                compute_ms=scenario.engine.transcode_ms,
                # One evaluation is one run of the detector.
                compute_us_per_evaluation=config.detect_us_per_pixel
                * detect_pixels((source.width, source.height)),
                label=f"{codec} {rung.rate_kbps:g}k {rung.width}x{rung.height}@{rung.fps:g}",
            )
        )
    return tuple(points)


def model_point(codec: str, scenario: Scenario, ladder, source) -> tuple[OperatingPoint, ...]:
    """The model codec's one point, at the source's size (its config section's rate and fps)."""
    config = getattr(scenario.engine, spec(codec).config_section)
    return (
        OperatingPoint(
            codec=codec,
            rate_kbps=config.rate_kbps,
            fps=min(config.fps, float(source.fps)),
            width=source.width,
            height=source.height,
            # Quantise and range-code, and with light on fit it against the receiver's view.
            compute_ms=config.encode_ms + (config.light_ms if config.light else 0.0),
            compute_us_per_evaluation=config.track_us_per_evaluation,
            label=f"{codec} {config.rate_kbps:g}k {source.width}x{source.height}",
        ),
    )


def ladder_points(codec: str, scenario: Scenario, ladder, source) -> tuple[OperatingPoint, ...]:
    """The full-frame codec's rungs, from its ladder."""
    return full_frame_points(ladder, codec=codec, transcode_ms=scenario.engine.transcode_ms)


BUILDERS: dict[Role, Callable[..., tuple[OperatingPoint, ...]]] = {
    Role.FULL_FRAME: ladder_points,
    Role.REGION: region_points,
    Role.MODEL: model_point,
}


def operating_points(scenario: Scenario, ladder, source, *, with_model: bool) -> tuple:
    """The engine's ladder: the model codec's point (`with_model`: the run has its
    description) below the region rungs (when enabled) below the full-frame rungs."""
    points = BUILDERS[Role.FULL_FRAME](scenario.engine.codec, scenario, ladder, source)
    for role in (Role.REGION, Role.MODEL) if with_model else (Role.REGION,):
        for name in names(role):
            points = BUILDERS[role](name, scenario, ladder, source) + points
    return points
