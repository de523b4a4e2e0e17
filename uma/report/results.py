"""Read one run's result folder (`frames.csv`, `events.csv`, `metrics.json`) for the reports.

Units as in the column names: ms, kbit/s, bits, dB. Missing or malformed files are a
`ConfigError` naming the file (exit 2), never a traceback.
"""

from __future__ import annotations

import csv
import io
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


def _is_float(text: str) -> bool:
    try:
        _float(text)
    except ValueError:
        return False
    return True


def _read_metrics(path: Path) -> dict[str, Any]:
    from uma.metrics.results import read_metrics

    metrics = read_metrics(path)
    if metrics is None:
        raise ConfigError(f"{path}: missing; expected the results of a finished run")
    return metrics


def _read_csv(path: Path) -> tuple[list[dict[str, str]], list[int]]:
    """Rows of a result CSV and the line each ends on; `ConfigError` naming file and line."""
    try:
        text = path.read_bytes().decode("utf-8")
    except UnicodeDecodeError as err:
        raise ConfigError(
            f"{path}: expected UTF-8 text ({err.reason} at byte {err.start})"
        ) from None
    except OSError as err:
        raise ConfigError(f"{path}: cannot read ({err.strerror or err})") from None
    reader = csv.DictReader(io.StringIO(text, newline=""))
    rows, lines = [], []
    try:
        for row in reader:
            if None in row or None in row.values():
                raise ConfigError(
                    f"{path}:{reader.line_num}: expected {len(reader.fieldnames or [])} fields "
                    f"(the file is truncated or damaged)"
                )
            rows.append(row)
            lines.append(reader.line_num)
    except csv.Error as err:
        raise ConfigError(f"{path}:{reader.line_num}: malformed CSV ({err})") from None
    return rows, lines


def read_run(folder: str | Path) -> RunFiles:
    """The three result files of a run folder."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ConfigError(f"{folder}: expected a results folder (as `uma run` writes)")
    paths = {name: folder / name for name in ("frames.csv", "events.csv", "metrics.json")}
    for path in paths.values():
        if not path.is_file():
            raise ConfigError(f"{path}: missing; expected the results of a finished run")
    metrics = _read_metrics(paths["metrics.json"])
    rows, _ = _read_csv(paths["frames.csv"])
    columns: dict[str, np.ndarray] = {}
    for name in rows[0] if rows else []:
        values = [row[name] for row in rows]
        try:
            columns[name] = (
                np.array([_float(v) for v in values]) if name in _NUMERIC else np.array(values)
            )
        except ValueError:
            line = next(i for i, v in enumerate(values, 2) if not _is_float(v))
            raise ConfigError(
                f"{paths['frames.csv']}:{line} ({name}): expected a number, got "
                f"{values[line - 2][:40]!r}"
            ) from None
    event_rows, lines = _read_csv(paths["events.csv"])
    events = []
    for row, line in zip(event_rows, lines, strict=True):
        try:
            events.append((float(row["time_ms"]), row["kind"], row["detail"]))
        except (KeyError, TypeError, ValueError):
            raise ConfigError(
                f"{paths['events.csv']}:{line}: expected time_ms,kind,detail, got {row!r:.60}"
            ) from None
    missing = [name for name in ("capture_ms", "display_ms", "frozen") if name not in columns]
    if missing:
        raise ConfigError(f"{paths['frames.csv']}: expected columns {', '.join(missing)}")
    return RunFiles(folder, columns, events, metrics)
