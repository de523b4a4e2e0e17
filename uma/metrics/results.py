"""Write one run's results: `scenario.yaml`, `frames.csv`, `events.csv`, `metrics.json`.

Each file is written atomically (temporary file, then `os.replace`), and `metrics.json` last, so
a reader that finds it finds the rest complete.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from uma.atomic import atomic_write_text

__all__ = ["write_results", "events_csv"]


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
    """Write the four result files into `out_dir` (created if needed); returns `out_dir`."""
    out = Path(out_dir)
    atomic_write_text(out / "scenario.yaml", scenario_yaml)
    atomic_write_text(out / "frames.csv", frames_csv)
    atomic_write_text(out / "events.csv", events_csv_text)
    atomic_write_text(out / "metrics.json", json.dumps(metrics, indent=2, sort_keys=False) + "\n")
    return out
