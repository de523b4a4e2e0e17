"""Read one run's result folder (`frames.csv`, `events.csv`, `metrics.json`) for the reports.

Units as in the column names: ms, kbit/s, bits, dB. Missing or malformed files are a
`ConfigError` naming the file (exit 2), never a traceback.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from uma.errors import ConfigError

__all__ = ["RunFiles", "read_run"]

_NUMERIC = (
    "frame", "capture_ms", "display_ms", "capacity_kbps", "estimate_kbps", "rung", "width",
    "height", "scheduled", "sent", "keyframe", "size_bits", "arrival_ms", "decoded",
    "shown_frame", "frozen", "delay_ms", "psnr_db", "ssim", "psnr_face_db", "ssim_face",
)  # fmt: skip


@dataclass(frozen=True)
class RunFiles:
    folder: Path
    frames: dict[str, np.ndarray]
    events: list[tuple[float, str, str]]  # (time_ms, kind, detail)
    metrics: dict[str, Any]


def _float(text: str) -> float:
    return float(text) if text != "" else float("nan")


def read_run(folder: str | Path) -> RunFiles:
    """The three result files of a run folder."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ConfigError(f"{folder}: expected a results folder (as `uma run` writes)")
    paths = {name: folder / name for name in ("frames.csv", "events.csv", "metrics.json")}
    for path in paths.values():
        if not path.is_file():
            raise ConfigError(f"{path}: missing; expected the results of a finished run")
    try:
        metrics = json.loads(paths["metrics.json"].read_text(encoding="utf-8"))
        with open(paths["frames.csv"], newline="", encoding="utf-8") as handle:
            rows = list(csv.DictReader(handle))
        columns: dict[str, np.ndarray] = {}
        for name in rows[0] if rows else []:
            values = [row[name] for row in rows]
            columns[name] = (
                np.array([_float(v) for v in values]) if name in _NUMERIC else np.array(values)
            )
        with open(paths["events.csv"], newline="", encoding="utf-8") as handle:
            events = [
                (float(row["time_ms"]), row["kind"], row["detail"])
                for row in csv.DictReader(handle)
            ]
    except (ValueError, KeyError, TypeError) as err:
        raise ConfigError(f"{folder}: malformed result files ({err})") from None
    missing = [name for name in ("capture_ms", "display_ms", "frozen") if name not in columns]
    if missing:
        raise ConfigError(f"{paths['frames.csv']}: expected columns {', '.join(missing)}")
    return RunFiles(folder, columns, events, metrics)
