"""Write one run's results: `scenario.yaml`, `frames.csv`, `events.csv`, `metrics.json`.

The folder is written whole or not at all (`uma.atomic.atomic_dir`): a folder that held an
earlier run holds, after any failure or kill, that earlier run whole, or else the new one whole.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from uma.atomic import atomic_dir

__all__ = ["write_results", "events_csv", "RUN_FILES"]

# What a run's folder may hold and a new run may therefore replace: the result files, the
# pictures and video `uma report` draws from them, a failed sweep point's error, and the
# temporary files of older versions of uma.
RUN_FILES = (
    "scenario.yaml",
    "metrics.json",
    "frames.csv",
    "events.csv",
    "error.txt",
    "timeline*.png",
    "receiver*.mp4",
    ".*.tmp",
)


def events_csv(events: Iterable[Any]) -> str:
    """Events (objects with `time_s`, `kind`, `detail`) as CSV with a `time_ms` column."""
    lines = ["time_ms,kind,detail"]
    for event in events:
        detail = str(event.detail).replace('"', "'")
        lines.append(f'{event.time_s * 1000.0:.3f},{event.kind},"{detail}"')
    return "\n".join(lines) + "\n"


def write_results(
    out_dir: str | Path,
    *,
    scenario_yaml: str,
    metrics: dict[str, Any],
    frames_csv: str,
    events_csv_text: str,
) -> Path:
    """Replace folder `out_dir` by the four result files, whole; returns `out_dir`.

    Raises `OutputError` (nothing replaced) when `out_dir` holds files other than `RUN_FILES`.
    """
    out = Path(out_dir)
    files = {
        "scenario.yaml": scenario_yaml,
        "frames.csv": frames_csv,
        "events.csv": events_csv_text,
        "metrics.json": json.dumps(metrics, indent=2, sort_keys=False) + "\n",
    }
    with atomic_dir(out, replaceable=RUN_FILES) as staging:
        for name, text in files.items():
            with open(staging / name, "w", encoding="utf-8", newline="\n") as handle:
                handle.write(text)
    return out
