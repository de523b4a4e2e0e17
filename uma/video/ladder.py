"""A codec's rate ladder: rungs of (rate, size, frame rate) and the encoder settings, read from
`codecs/h264.yaml` (or `vp8.yaml`, `av1.yaml`).

Units: rates in kbit/s, sizes in pixels, frame rates in frames/s, the VBV buffer in frame
intervals. A file holds `rungs` (a list, lowest rate first) and optionally `codec` (`h264`, the
default, `vp8` or `av1`) and `encoder`, whose keys are the codec's: for H.264 `preset`, `tune`,
`keyint_frames`, `vbv_frames` (see `uma.video.h264`), for the others those of
`uma.video.vp8.VP8Settings` and `uma.video.av1.AV1Settings`. Errors name the file, the line and
the key path, e.g. `codecs/h264.yaml:9 (rungs[3].fps): expected a positive number, got -1`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from uma.errors import ConfigError
from uma.video.h264 import PRESETS

if TYPE_CHECKING:  # uma.config's package import pulls in pydantic; load it only when reading
    from uma.config.yamlfile import KeyLines

__all__ = [
    "Rung",
    "EncoderSettings",
    "Ladder",
    "open_span",
    "load_ladder",
    "default_ladder_path",
    "LADDER_CODECS",
    "settings_class",
]

_RUNG_KEYS = ("rate_kbps", "width", "height", "fps")
_ENCODER_KEYS = ("preset", "tune", "keyint_frames", "vbv_frames")
LADDER_CODECS = ("h264", "vp8", "av1")  # the values of a ladder file's `codec`


# What a rung may ask for: a source is at most 4096 px a side and 120 frames/s (uma/config),
# and no codec here takes more than 1 Gbit/s.
MAX_RATE_KBPS = 1e6
MAX_SIDE_PX = 4096
MAX_FPS = 120.0


def _positive(
    value: Any, where: str, *, integer: bool = False, even: bool = False, maximum: float = math.inf
):
    ok = isinstance(value, int | float) and not isinstance(value, bool)
    ok = ok and math.isfinite(value) and value > 0
    if ok and integer:
        ok = float(value).is_integer()
    if not ok:
        kind = "a positive integer" if integer else "a positive number"
        raise ConfigError(f"{where}: expected {kind}, got {value!r}")
    if value > maximum:
        raise ConfigError(f"{where}: {value:g} is above the maximum {maximum:g}")
    if even and int(value) % 2:
        raise ConfigError(f"{where}: expected an even number (4:2:0 chroma), got {value!r}")
    return int(value) if integer else float(value)


@dataclass(frozen=True)
class Rung:
    """One operating point: libx264's target rate and the picture size and rate it codes."""

    rate_kbps: float
    width: int
    height: int
    fps: float

    def __post_init__(self) -> None:
        _positive(self.rate_kbps, "rung rate_kbps")
        _positive(self.width, "rung width", integer=True, even=True)
        _positive(self.height, "rung height", integer=True, even=True)
        _positive(self.fps, "rung fps")

    @property
    def label(self) -> str:
        """`64k 176x144@12.5`, for tables and logs."""
        return f"{self.rate_kbps:g}k {self.width}x{self.height}@{self.fps:.3g}"


@dataclass(frozen=True)
class EncoderSettings:
    """libx264 settings shared by every rung (and the sender unless its scenario says otherwise)."""

    preset: str = "ultrafast"
    tune: str = "zerolatency"
    keyint_frames: int = 250
    vbv_frames: float = 4.0

    KEYS = _ENCODER_KEYS

    def __post_init__(self) -> None:
        _check_encoder(asdict(self), lambda key: f"encoder {key}")

    @classmethod
    def check(cls, values: dict[str, Any], where: Callable[[str], str]) -> None:
        """Raise `ConfigError` naming `where(key)` for the first bad value in `values`."""
        _check_encoder(values, where)

    def kwargs(self) -> dict[str, Any]:
        """Keyword arguments for `H264Encoder`."""
        return asdict(self)


@dataclass(frozen=True)
class Ladder:
    """Rungs in strictly ascending rate; `source` names the file for messages.

    `encoder` is the settings object of `codec` (`EncoderSettings` for H.264, `VP8Settings`,
    `AV1Settings`); its `kwargs()` are the keyword arguments of that codec's encoder.
    """

    rungs: tuple[Rung, ...]
    encoder: Any = field(default_factory=EncoderSettings)
    source: str = "<ladder>"
    codec: str = "h264"

    def __post_init__(self) -> None:
        expected = settings_class(self.codec, f"{self.source}: codec")
        if not isinstance(self.encoder, expected):
            raise ConfigError(
                f"{self.source}: encoder: expected {expected.__name__} for codec {self.codec!r}, "
                f"got {type(self.encoder).__name__}"
            )
        if not self.rungs:
            raise ConfigError(f"{self.source}: rungs: expected at least one rung")
        for index in range(1, len(self.rungs)):
            below, rung = self.rungs[index - 1].rate_kbps, self.rungs[index].rate_kbps
            if rung <= below:
                raise ConfigError(
                    f"{self.source}: rungs[{index}].rate_kbps: expected more than the rung "
                    f"below ({below:g}), got {rung:g}"
                )

    def open_span(self, rung: Rung) -> tuple[float, float]:
        """(fps, max_rate_kbps) to open an encoder for `rung` with, so that `set_target`
        reaches every rung of the same size without a key frame.

        The highest frame rate among the rungs of `rung`'s size, and the highest rate asked of
        an encoder opened at that frame rate: a rung at a lower frame rate asks
        `rate_kbps * fps / rung.fps` (x264 with `tune=zerolatency` budgets per frame; see
        `H264Encoder.set_target`).
        """
        size = (rung.width, rung.height)
        return open_span([r for r in self.rungs if (r.width, r.height) == size] or [rung])


def open_span(same: Sequence) -> tuple[float, float]:
    """(fps, max_rate_kbps) to open one encoder with so that `set_target` reaches each of
    `same` (rungs or operating points of one stream: each with `fps` and `rate_kbps`): the
    highest frame rate, and the highest rate a member asks at it (`Ladder.open_span`)."""
    fps = max(r.fps for r in same)
    return fps, max(r.rate_kbps * fps / r.fps for r in same)


def _check_encoder(values: dict[str, Any], where: Callable[[str], str]) -> None:
    preset, tune = values.get("preset", "ultrafast"), values.get("tune", "zerolatency")
    if preset not in PRESETS:
        raise ConfigError(
            f"{where('preset')}: expected one of {', '.join(PRESETS)}, got {preset!r}"
        )
    if not isinstance(tune, str) or "zerolatency" not in tune.split(","):
        raise ConfigError(
            f"{where('tune')}: expected tunes including 'zerolatency' (one frame out per frame "
            f"in), got {tune!r}"
        )
    _positive(values.get("keyint_frames", 1), where("keyint_frames"), integer=True)
    vbv_frames = values.get("vbv_frames", 1.0)
    if _positive(vbv_frames, where("vbv_frames")) < 1:
        raise ConfigError(f"{where('vbv_frames')}: expected at least 1, got {vbv_frames!r}")


def settings_class(codec: str, where: str = "codec") -> type:
    """The encoder-settings class of a ladder's `codec`; `ConfigError` naming `where` if unknown."""
    if codec == "h264":
        return EncoderSettings
    if codec == "vp8":
        from uma.video.vp8 import VP8Settings

        return VP8Settings
    if codec == "av1":
        from uma.video.av1 import AV1Settings

        return AV1Settings
    raise ConfigError(f"{where}: expected one of {', '.join(LADDER_CODECS)}, got {codec!r}")


def default_ladder_path(codec: str = "h264") -> Path:
    """The project's ladder file of `codec`, `codecs/<codec>.yaml`."""
    from uma.paths import codecs_dir

    settings_class(codec)
    return codecs_dir() / f"{codec}.yaml"


def _mapping(
    item: Any, allowed: tuple[str, ...], required: tuple[str, ...], lines: KeyLines, key_path: tuple
) -> dict:
    """`item` checked to be a mapping with only `allowed` keys and every `required` one."""
    expected = f"expected keys {', '.join(allowed)}"
    if not isinstance(item, dict):
        raise ConfigError(f"{lines.where(key_path)}: expected a mapping ({expected}), got {item!r}")
    unknown = [key for key in item if key not in allowed]
    if unknown:
        from uma.config.yamlfile import format_key_path

        # the line of the unknown key itself, the key path of its parent
        line = lines.line_of(key_path + (unknown[0],))
        where = f"{lines.path}:{line}" if line else str(lines.path)
        where += f" ({format_key_path(key_path)})" if key_path else ""
        raise ConfigError(f"{where}: unknown key {unknown[0]!r}; {expected}")
    missing = [key for key in required if key not in item]
    if missing:
        raise ConfigError(f"{lines.where(key_path)}: missing key {missing[0]!r}; {expected}")
    return item


def load_ladder(path: str | Path | None = None) -> Ladder:
    """Read and validate a ladder file (the project's `codecs/h264.yaml` by default)."""
    from uma.config.yamlfile import load_yaml  # imports PyYAML

    path = Path(path) if path is not None else default_ladder_path()
    data, lines = load_yaml(path)
    top = _mapping(data, ("rungs", "encoder", "codec"), ("rungs",), lines, ())
    codec = top.get("codec", "h264")
    settings = settings_class(codec, lines.where(("codec",)))
    if not isinstance(top["rungs"], list):
        raise ConfigError(
            f"{lines.where(('rungs',))}: expected a list of rungs, got {top['rungs']!r}"
        )
    if not top["rungs"]:
        raise ConfigError(f"{lines.where(('rungs',))}: expected at least one rung")
    rungs = []
    for index, item in enumerate(top["rungs"]):
        key = ("rungs", index)
        item = _mapping(item, _RUNG_KEYS, _RUNG_KEYS, lines, key)
        rungs.append(
            Rung(
                rate_kbps=_positive(
                    item["rate_kbps"], lines.where(key + ("rate_kbps",)), maximum=MAX_RATE_KBPS
                ),
                width=_positive(
                    item["width"],
                    lines.where(key + ("width",)),
                    integer=True,
                    even=True,
                    maximum=MAX_SIDE_PX,
                ),
                height=_positive(
                    item["height"],
                    lines.where(key + ("height",)),
                    integer=True,
                    even=True,
                    maximum=MAX_SIDE_PX,
                ),
                fps=_positive(item["fps"], lines.where(key + ("fps",)), maximum=MAX_FPS),
            )
        )
    for index in range(1, len(rungs)):
        if rungs[index].rate_kbps <= rungs[index - 1].rate_kbps:
            raise ConfigError(
                f"{lines.where(('rungs', index, 'rate_kbps'))}: expected more than the rung below "
                f"({rungs[index - 1].rate_kbps:g}), got {rungs[index].rate_kbps:g}"
            )
    encoder = settings()
    if "encoder" in top:
        values = _mapping(top["encoder"], settings.KEYS, (), lines, ("encoder",))
        settings.check(values, lambda key: lines.where(("encoder", key)))
        encoder = settings(**values)
    return Ladder(tuple(rungs), encoder=encoder, source=str(path), codec=codec)
