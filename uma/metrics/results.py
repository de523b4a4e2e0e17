"""Write one run's results: `scenario.yaml`, `frames.csv`, `events.csv`, `metrics.json`.

The folder is written whole or not at all (`uma.atomic.atomic_dir`): a folder that held an
earlier run holds, after any failure or kill, that earlier run whole, or else the new one whole.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from uma.atomic import atomic_dir

__all__ = ["write_results", "read_metrics", "events_csv", "RUN_FILES"]

# A run's metrics are a few kB; a file far past that is not one.
MAX_METRICS_BYTES = 64 * 2**20

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


def read_metrics(path: str | Path) -> dict[str, Any] | None:
    """The mapping in metrics file `path`; None when there is no such file.

    A file that is there but not a JSON object (truncated, garbled, not UTF-8) is a
    `ConfigError` naming the file and line, not "missing".
    """
    from uma.errors import ConfigError
    from uma.paths import read_capped

    path = Path(path)
    if not os.path.lexists(path):
        return None
    # A FIFO or device, a symlink loop and a file past the cap are refused in one line.
    data = read_capped(
        path, max_bytes=MAX_METRICS_BYTES, error=ConfigError, what="metrics.json of a finished run"
    )
    try:
        metrics = json.loads(data.decode("utf-8"))
    except RecursionError:
        raise ConfigError(
            f"{path}:1: expected the JSON metrics of a finished run, got JSON nested too deeply"
        ) from None
    except UnicodeDecodeError as err:
        line = data[: err.start].count(b"\n") + 1
        raise ConfigError(
            f"{path}:{line}: expected UTF-8 JSON, got byte 0x{data[err.start]:02x}"
        ) from None
    except json.JSONDecodeError as err:
        # A cut-off file fails at its end, or inside a string that runs to its end.
        cut = err.pos >= len(data.rstrip()) or err.msg.startswith("Unterminated string")
        cause = "truncated" if cut else "unparseable"
        raise ConfigError(
            f"{path}:{err.lineno}: expected the JSON metrics of a finished run, got {cause} "
            f"JSON ({err.msg}, column {err.colno})"
        ) from None
    if not isinstance(metrics, dict):
        raise ConfigError(
            f"{path}:1: expected a JSON object of metrics, got {type(metrics).__name__}"
        )
    return metrics
