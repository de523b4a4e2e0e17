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
from uma.config.types import Bool, NonNegInt, PosInt, PosNum, Section, Str

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
]


class SourceConfig(Section):
    """What the sender captures: a video file, raw YUV 4:2:0, or a built-in synthetic source."""

    kind: Literal["pattern", "file", "yuv", "talking-head"] = "pattern"
    path: Str | None = None
    width: PosInt = 352
    height: PosInt = 288
    fps: PosNum = 25.0
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

    name: Annotated[str, Strict(), Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")]
    description: Str = ""
    seed: NonNegInt = 0
    duration_s: PosNum | None = None
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
        return self.model_copy(update={"route": route, "source": source, "engine": engine})

    def with_seed(self, seed: int) -> Scenario:
        return self.model_copy(update={"seed": seed})
