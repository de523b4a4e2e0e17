"""Figures other systems published per trace, read from a CSV, to print beside uma's.

Units: delays in ms, SSIM in dB (10 log10(1 / (1 - SSIM))).

The file has `#` comment lines, then a header with at least `trace`, `system`, `delay_p95_ms`
and `ssim_db_mean`, one row per trace and system (e.g. Salsify's NSDI 2018 results, in the
shared data's `published/salsify-nsdi18.csv`). A trace file is matched to a row by its name
without the Mahimahi direction or compression suffixes (`TMobile-UMTS-driving.down` is
`TMobile-UMTS-driving`), case-insensitively.
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path

from uma.errors import ConfigError

__all__ = ["read_published", "trace_name", "published_for"]

REQUIRED = ("trace", "system", "delay_p95_ms", "ssim_db_mean")
SUFFIXES = (".gz", ".down", ".up", ".log", ".txt")


def trace_name(path: str | os.PathLike) -> str:
    """A trace file's name without direction and compression suffixes."""
    name = Path(path).name
    changed = True
    while changed:
        changed = False
        for suffix in SUFFIXES:
            if name.lower().endswith(suffix) and len(name) > len(suffix):
                name, changed = name[: -len(suffix)], True
    return name


def _number(text: str, where: str, key: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ConfigError(f"{where}: {key}: expected a number, got {text!r}") from None
    if not math.isfinite(value) or value < 0:
        raise ConfigError(f"{where}: {key}: expected a finite non-negative number, got {text!r}")
    return value


def read_published(path: str | os.PathLike) -> dict[str, dict[str, dict[str, float]]]:
    """trace name (lower case) -> system -> {`delay_p95_ms`, `ssim_db`}; errors name the line."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        reason = getattr(err, "strerror", None) or "not UTF-8 text"
        raise ConfigError(f"{path}: cannot read published figures ({reason})") from None
    numbered = [
        (number, line)
        for number, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not numbered:
        raise ConfigError(f"{path}: expected a CSV header with {', '.join(REQUIRED)}, got no lines")
    header_line, header_text = numbered[0]
    header = [cell.strip() for cell in next(csv.reader([header_text]))]
    missing = [key for key in REQUIRED if key not in header]
    if missing:
        raise ConfigError(
            f"{path}:{header_line}: expected columns {', '.join(REQUIRED)}, "
            f"missing {', '.join(missing)}"
        )
    out: dict[str, dict[str, dict[str, float]]] = {}
    for number, line in numbered[1:]:
        cells = next(csv.reader([line]))
        where = f"{path}:{number}"
        if len(cells) != len(header):
            raise ConfigError(f"{where}: expected {len(header)} fields, got {len(cells)}")
        row = dict(zip(header, (cell.strip() for cell in cells), strict=True))
        if not row["trace"] or not row["system"]:
            raise ConfigError(f"{where}: expected a trace and a system name, got an empty one")
        figures = {
            "delay_p95_ms": _number(row["delay_p95_ms"], where, "delay_p95_ms"),
            "ssim_db": _number(row["ssim_db_mean"], where, "ssim_db_mean"),
        }
        systems = out.setdefault(row["trace"].lower(), {})
        if row["system"] in systems:
            raise ConfigError(f"{where}: {row['trace']} {row['system']} given twice")
        systems[row["system"]] = figures
    return out


def published_for(
    trace: str | os.PathLike, path: str | os.PathLike | None
) -> dict[str, dict[str, float]]:
    """The figures published for `trace`'s name in the file at `path`; {} without a file or row."""
    if path is None or not Path(path).is_file():
        return {}
    return read_published(path).get(trace_name(trace).lower(), {})
