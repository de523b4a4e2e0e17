"""The scenario schema: one YAML file parsed once into frozen, validated objects.

Units live in key names (`rate_kbps`, `delay_ms`, `duration_s`, `queue_bytes`). Numbers must be
numbers (a string such as "2 Mbit/s" is refused, so a unit cannot hide in a value), unknown keys
are refused, and relative paths are resolved against the scenario file's folder when loaded, so
the resolved scenario written beside the results repeats the run from anywhere.
"""

from __future__ import annotations

from os.path import realpath
from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field, Strict, model_validator

from uma.config.codecs import FaceRegionConfig, FaceRungConfig, MbcConfig
from uma.config.engine import (
    ESTIMATOR_KINDS,
    POLICY_NAMES,
    SWITCHING_NAMES,
    EngineConfig,
    EstimatorConfig,
    SwitchingConfig,
)
from uma.config.faults import (
    FaultsConfig,
    LossBurstConfig,
    OutageConfig,
    ReorderConfig,
    SilenceConfig,
)
from uma.config.network import (
    DownlinkConfig,
    FeedbackConfig,
    SegmentConfig,
    TechnologyOverride,
    UplinkConfig,
)
from uma.config.receiver import AdaptivePlayoutConfig, MetricsConfig, ReceiverConfig
from uma.config.types import Bool, PosInt, PosNum, Section, Str, bounded

__all__ = [
    "Scenario",
    "SourceConfig",
    "SenderConfig",
    "UplinkConfig",
    "DownlinkConfig",
    "TechnologyOverride",
    "SegmentConfig",
    "FeedbackConfig",
    "EstimatorConfig",
    "EngineConfig",
    "ReceiverConfig",
    "AdaptivePlayoutConfig",
    "MetricsConfig",
    "POLICY_NAMES",
    "FaultsConfig",
    "LossBurstConfig",
    "OutageConfig",
    "ReorderConfig",
    "SilenceConfig",
    "ESTIMATOR_KINDS",
    "SwitchingConfig",
    "MbcConfig",
    "FaceRegionConfig",
    "FaceRungConfig",
    "SWITCHING_NAMES",
    "MAX_DURATION_S",
    "MAX_SIDE_PX",
    "MAX_FPS",
    "MAX_WORK_PIXELS",
]


# What one run may hold: four hours (memory grows about 75 KB per simulated second), pictures
# up to 4K, and at most this many source pixels in all (CIF at 25 frames/s for 4 h is 3.6e10,
# 1080p at 30 frames/s for an hour 2.2e11).
MAX_DURATION_S = 4 * 3600.0
MAX_SIDE_PX = 4096
MAX_FPS = 120.0
MAX_WORK_PIXELS = 3e11
MAX_SEED = 2**63 - 1  # numpy's generators take any; this is what an int64 column holds


class SourceConfig(Section):
    """What the sender captures: a video file, raw YUV 4:2:0, or a built-in synthetic source."""

    kind: Literal["pattern", "file", "yuv", "talking-head"] = "pattern"
    path: Str | None = None
    # Up to 4K (DCI): a picture holds several copies of itself per frame in the codec chain.
    width: bounded(16, MAX_SIDE_PX, integer=True) = 352
    height: bounded(16, MAX_SIDE_PX, integer=True) = 288
    fps: bounded(0, MAX_FPS, open_low=True) = 25.0
    loop: Bool = True

    @model_validator(mode="after")
    def _path_needed(self) -> SourceConfig:
        if self.kind in ("file", "yuv") and not self.path:
            raise ValueError(f"source kind '{self.kind}' needs 'path' (a video file)")
        if self.width % 2 or self.height % 2:
            raise ValueError(
                f"width and height must be even for 4:2:0, got {self.width}x{self.height}"
            )
        return self


class SenderConfig(Section):
    """The sender's own H.264 encoding, at a high rate over the good uplink."""

    rate_kbps: PosNum = 1500.0
    preset: Str = "ultrafast"
    keyint_frames: PosInt = 250


class Scenario(Section):
    """A whole experiment; `Scenario.load(path)` is the way in (`uma.config.load_scenario`)."""

    # The results folder's name (results/<name>): short enough for uma's staging name beside it.
    name: Annotated[str, Strict(), Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]*$", max_length=100)]
    description: Str = ""
    seed: bounded(0, MAX_SEED, integer=True) = 0
    duration_s: bounded(0, MAX_DURATION_S, open_low=True) | None = None
    source: SourceConfig = Field(default_factory=SourceConfig)
    sender: SenderConfig = Field(default_factory=SenderConfig)
    uplink: UplinkConfig = Field(default_factory=UplinkConfig)
    downlink: DownlinkConfig = Field(default_factory=DownlinkConfig)
    route: tuple[SegmentConfig, ...] = Field(min_length=1)
    feedback: FeedbackConfig = Field(default_factory=FeedbackConfig)
    engine: EngineConfig = Field(default_factory=EngineConfig)
    receiver: ReceiverConfig = Field(default_factory=ReceiverConfig)
    metrics: MetricsConfig = Field(default_factory=MetricsConfig)
    faults: FaultsConfig = Field(default_factory=FaultsConfig)

    @model_validator(mode="after")
    def _bounded_run(self) -> Scenario:
        """At least one frame, a route no longer than a run may be, and bounded total work."""
        if self.duration_s is None and self.route_duration_s > MAX_DURATION_S:
            raise ValueError(
                f"the route's {self.route_duration_s:g} s is above the maximum "
                f"{MAX_DURATION_S:g} s a run may last; set duration_s or shorten the route"
            )
        duration_s, fps = self.run_duration_s, self.source.fps
        if duration_s * fps < 1:
            raise ValueError(
                f"duration_s ({duration_s:g}) x source.fps ({fps:g}) holds no frame; "
                f"expected at least {1 / fps:g} s"
            )
        work = duration_s * fps * self.source.width * self.source.height
        if work > MAX_WORK_PIXELS:
            raise ValueError(
                f"duration_s ({duration_s:g}) x source.fps ({fps:g}) x source.width "
                f"({self.source.width}) x source.height ({self.source.height}) is {work:.3g} "
                f"pixels to simulate, above the maximum {MAX_WORK_PIXELS:.0e}; shorten the run "
                f"or make the picture smaller"
            )
        return self

    @property
    def route_duration_s(self) -> float:
        return sum(segment.duration_s for segment in self.route)

    @property
    def run_duration_s(self) -> float:
        """Simulated capture time: `duration_s`, or the whole route when not given."""
        return self.duration_s if self.duration_s is not None else self.route_duration_s

    def resolved_paths(self, base_dir: Path) -> Scenario:
        """A copy whose relative file paths are made absolute against `base_dir`."""

        def absolute(path: str | None) -> str | None:
            if path is None:
                return None
            candidate = Path(path).expanduser()
            # realpath, not resolve(): a symlink loop is left for `_check_files` to name.
            return str(candidate if candidate.is_absolute() else realpath(base_dir / candidate))

        route = tuple(
            segment.model_copy(update={"trace": absolute(segment.trace)}) for segment in self.route
        )
        source = self.source.model_copy(update={"path": absolute(self.source.path)})
        mbc = self.engine.mbc.model_copy(
            update={"description": absolute(self.engine.mbc.description)}
        )
        engine = self.engine.model_copy(update={"ladder": absolute(self.engine.ladder), "mbc": mbc})
        feedback = self.feedback.model_copy(update={"trace": absolute(self.feedback.trace)})
        return self.model_copy(
            update={"route": route, "source": source, "engine": engine, "feedback": feedback}
        )

    def with_seed(self, seed: int) -> Scenario:
        """A copy with `seed`, checked against the key's bound (a copy skips validation)."""
        if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
            raise ValueError(f"seed: expected an integer from 0 to 2**63 - 1, got {seed!r}")
        return self.model_copy(update={"seed": seed})
