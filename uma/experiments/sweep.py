"""Run every point of an experiment on an executor; resumable, failures recorded.

Layout of `OUT/`: `points/<hash>/` holds each run's result files (as `uma run` writes them,
whole, or `error.txt` for a failed point); `sweep.csv` and `sweep.parquet` one row per point:
point, hash, repeat, every grid key, seed, status, error, then every metric. Status is `ok`,
`failed`, or `missing` (not run yet: the sweep is incomplete). The table is written before the
first point runs (every point not yet complete `missing`), again every few seconds as points
finish, and when the sweep ends or is interrupted, so it never lists fewer points than the grid
nor calls a point done that is not. A point whose folder already holds a `metrics.json` is not
run again: its hash covers the scenario and the contents of the files it reads.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from uma.errors import OutputError
from uma.experiments.executor import Executor
from uma.experiments.point import completed_metrics, point_task, run_point
from uma.experiments.spec import Experiment
from uma.experiments.table import STATUSES, cell, flatten, write_table
from uma.experiments.uplink_store import StoreSettings

__all__ = ["SweepResult", "run_sweep", "check_sweep_out", "STATUSES", "SWEEP_FILES"]

# What a sweep folder holds: its tables, and `points/` (uma's temporaries aside).
SWEEP_FILES = ("sweep.csv", "sweep.parquet")
SWEEP_FOLDERS = ("points",)

_TABLE_EVERY_S = 2.0  # rewrite the table at most this often while points finish


@dataclass(frozen=True)
class SweepResult:
    rows: tuple[dict[str, Any], ...]
    ran: int
    skipped: int
    failed: int
    csv_path: Path
    parquet_path: Path
    missing: int = 0


_MISSING = {"status": "missing", "error": "", "metrics": {}}


def _row(experiment: Experiment, point, reply: dict[str, Any]) -> dict[str, Any]:
    row: dict[str, Any] = {"point": point.index, "hash": point.hash, "repeat": point.repeat}
    row |= {key: cell(point.values[key]) for key in experiment.grid_keys}
    row |= {"seed": point.scenario.seed, "status": reply["status"], "error": reply["error"]}
    for key, value in flatten(reply.get("metrics") or {}).items():
        row.setdefault(key, cell(value))
    return row


def check_sweep_out(out_dir: str | Path, *, what: str = "--out") -> Path:
    """Raise `OutputError` unless `out_dir` can take a sweep: absent, empty, or a sweep's folder.

    A folder holding a run's results (or anything else uma did not write there as a sweep) is
    refused before any point runs, so a sweep folder and a run folder never mix.
    """
    from uma.atomic import check_replaceable, prepare_out_dir

    out = prepare_out_dir(out_dir, what=what)
    check_replaceable(out, SWEEP_FILES, folders=SWEEP_FOLDERS, what=what)
    return out


def _pending(
    experiment: Experiment, points_dir: Path, uplink: StoreSettings | None
) -> tuple[dict[int, dict[str, Any]], list[dict[str, Any]]]:
    """(the replies of the points already complete, the tasks of the others)."""
    replies: dict[int, dict[str, Any]] = {}
    tasks = []
    store = None if uplink is None else uplink.task()
    for point in experiment.points:
        done = completed_metrics(points_dir / point.hash)
        if done is not None:
            replies[point.index] = {"status": "ok", "error": "", "metrics": done}
            continue
        tasks.append(
            point_task(
                point.scenario,
                points_dir / point.hash,
                index=point.index,
                hash=point.hash,
                uplink=store,
            )
        )
    return replies, tasks


def run_sweep(
    experiment: Experiment,
    out_dir: str | Path,
    executor: Executor,
    *,
    progress: Callable[[int, int], None] | None = None,
    uplink: StoreSettings | None = None,
) -> SweepResult:
    """Run the points not yet complete in `out_dir`, keeping the table of all of them current.

    `uplink`: the store of sender streams every point takes its stream from and adds to
    (`uma.experiments.uplink_store`; results are the same without it). It may not lie inside
    `out_dir` (`OutputError`): a sweep's folder holds its runs and tables only.

    An exception while points run (a failure of the executor, or `KeyboardInterrupt` from
    Ctrl-C or a SIGTERM handler) writes the table of what is done, the rest `missing`, and
    propagates.
    """
    out = check_sweep_out(out_dir)
    if uplink is not None and uplink.root.resolve().is_relative_to(out.resolve()):
        raise OutputError(
            f"UMA_CACHE: the store of sender streams {str(uplink.root)!r} lies inside the "
            f"sweep's folder {str(out)!r}; expected it elsewhere (or UMA_CACHE=off)"
        )
    points_dir = out / "points"
    csv_path, parquet_path = out / "sweep.csv", out / "sweep.parquet"
    replies, tasks = _pending(experiment, points_dir, uplink)
    skipped = len(replies)
    total = len(experiment.points)

    def table() -> tuple[dict[str, Any], ...]:
        rows = tuple(_row(experiment, p, replies.get(p.index, _MISSING)) for p in experiment.points)
        write_table(rows, csv_path, parquet_path)
        return rows

    try:
        table()  # before any point runs: an interrupted sweep is marked incomplete from the start
        if progress is not None:
            progress(skipped, total)
        written = time.monotonic()
        for reply in executor.map_unordered(run_point, tasks):
            replies[reply["index"]] = reply
            if progress is not None:
                progress(len(replies), total)
            if time.monotonic() - written >= _TABLE_EVERY_S:
                table()
                written = time.monotonic()
    except BaseException:
        table()
        raise
    rows = table()
    failed = sum(row["status"] == "failed" for row in rows)
    missing = sum(row["status"] == "missing" for row in rows)
    return SweepResult(rows, len(tasks), skipped, failed, csv_path, parquet_path, missing=missing)
