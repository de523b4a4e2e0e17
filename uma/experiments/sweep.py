"""Run every point of an experiment on an executor; resumable, failures recorded.

Layout of `OUT/`: `points/<hash>/` holds each run's result files (as `uma run` writes them,
or `error.txt` for a failed point); `sweep.csv` and `sweep.parquet` one row per point: point,
hash, repeat, every grid key, seed, status (`ok`, `failed`), error, then every metric. A point
whose folder already holds a complete `metrics.json` is not run again.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from uma.experiments.executor import Executor
from uma.experiments.point import completed_metrics, point_task, run_point
from uma.experiments.spec import Experiment
from uma.experiments.table import cell, flatten, write_table

__all__ = ["SweepResult", "run_sweep"]


@dataclass(frozen=True)
class SweepResult:
    rows: tuple[dict[str, Any], ...]
    ran: int
    skipped: int
    failed: int
    csv_path: Path
    parquet_path: Path


def _row(experiment: Experiment, point, reply: dict[str, Any]) -> dict[str, Any]:
    row: dict[str, Any] = {"point": point.index, "hash": point.hash, "repeat": point.repeat}
    row |= {key: cell(point.values[key]) for key in experiment.grid_keys}
    row |= {"seed": point.scenario.seed, "status": reply["status"], "error": reply["error"]}
    for key, value in flatten(reply.get("metrics") or {}).items():
        row.setdefault(key, cell(value))
    return row


def run_sweep(
    experiment: Experiment,
    out_dir: str | Path,
    executor: Executor,
    *,
    progress: Callable[[int, int], None] | None = None,
) -> SweepResult:
    """Run the points not yet complete in `out_dir`, then write the table of all of them."""
    out = Path(out_dir)
    points_dir = out / "points"
    replies: dict[int, dict[str, Any]] = {}
    tasks = []
    for point in experiment.points:
        done = completed_metrics(points_dir / point.hash)
        if done is not None:
            replies[point.index] = {"status": "ok", "error": "", "metrics": done}
        else:
            tasks.append(
                point_task(
                    point.scenario, points_dir / point.hash, index=point.index, hash=point.hash
                )
            )
    skipped = len(replies)
    total = len(experiment.points)
    if progress is not None:
        progress(skipped, total)
    for reply in executor.map_unordered(run_point, tasks):
        replies[reply["index"]] = reply
        if progress is not None:
            progress(len(replies), total)
    rows = tuple(_row(experiment, p, replies[p.index]) for p in experiment.points)
    csv_path, parquet_path = out / "sweep.csv", out / "sweep.parquet"
    write_table(rows, csv_path, parquet_path)
    failed = sum(row["status"] != "ok" for row in rows)
    return SweepResult(rows, len(tasks), skipped, failed, csv_path, parquet_path)
