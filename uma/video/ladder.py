"""The H.264 rate ladder: rungs of (rate, size, frame rate), read from `codecs/h264.yaml`.

Units: rates in kbit/s, sizes in pixels, frame rates in frames/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from uma.errors import ConfigError

__all__ = ["Rung", "Ladder", "load_ladder", "default_ladder_path"]


@dataclass(frozen=True)
class Rung:
    rate_kbps: float
    width: int
    height: int
    fps: float


@dataclass(frozen=True)
class Ladder:
    """Rungs in strictly ascending rate; `source` names the file for messages."""

    rungs: tuple[Rung, ...]
    source: str = "<ladder>"

    def __post_init__(self) -> None:
        if not self.rungs:
            raise ConfigError(f"{self.source}: rungs: expected at least one rung")
        for index in range(1, len(self.rungs)):
            if self.rungs[index].rate_kbps <= self.rungs[index - 1].rate_kbps:
                raise ConfigError(
                    f"{self.source}: rungs[{index}].rate_kbps: expected more than the rung "
                    f"below ({self.rungs[index - 1].rate_kbps}), got {self.rungs[index].rate_kbps}"
                )


def default_ladder_path() -> Path:
    from uma.paths import codecs_dir

    return codecs_dir() / "h264.yaml"


def _number(value, where: str, *, integer: bool = False, even: bool = False) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool)
    if ok and integer:
        ok = isinstance(value, int) or float(value).is_integer()
    if not ok or not math.isfinite(value) or value <= 0:
        kind = "a positive integer" if integer else "a positive number"
        raise ConfigError(f"{where}: expected {kind}, got {value!r}")
    if even and int(value) % 2:
        raise ConfigError(f"{where}: expected an even number (4:2:0), got {value!r}")
    return int(value) if integer else float(value)


def load_ladder(path: str | Path | None = None) -> Ladder:
    """Read and validate a ladder file (the project's `codecs/h264.yaml` by default)."""
    from uma.config.yamlfile import load_yaml

    path = Path(path) if path is not None else default_ladder_path()
    data, lines = load_yaml(path)
    if not isinstance(data, dict) or set(data) != {"rungs"} or not isinstance(data["rungs"], list):
        raise ConfigError(f"{lines.where(())}: expected a mapping with one key 'rungs' (a list)")
    rungs = []
    for index, item in enumerate(data["rungs"]):
        key = ("rungs", index)
        if not isinstance(item, dict) or set(item) != {"rate_kbps", "width", "height", "fps"}:
            raise ConfigError(
                f"{lines.where(key)}: expected keys rate_kbps, width, height, fps, got {item!r}"
            )
        rungs.append(
            Rung(
                rate_kbps=_number(item["rate_kbps"], lines.where(key + ("rate_kbps",))),
                width=_number(
                    item["width"], lines.where(key + ("width",)), integer=True, even=True
                ),
                height=_number(
                    item["height"], lines.where(key + ("height",)), integer=True, even=True
                ),
                fps=_number(item["fps"], lines.where(key + ("fps",))),
            )
        )
    return Ladder(tuple(rungs), source=str(path))
