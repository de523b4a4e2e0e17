"""Run one sweep point in whatever process an executor gives it, and write its folder whole.

The task is small (the resolved scenario as JSON-ready data and a folder name): the worker
opens its own source and traces, so nothing large travels to it. Any failure becomes a value
(`status: failed` and the error's line) so one bad point does not stop the others.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path
from typing import Any

__all__ = ["run_point", "point_task", "completed_metrics"]


def point_task(
    scenario, out_dir: str | Path, *, index: int, hash: str, uplink: dict | None = None
) -> dict[str, Any]:
    """The task for `run_point`: plain data that pickles small and travels to any worker.

    `uplink`: the store of sender streams the run takes its stream from and adds to
    (`uma.experiments.uplink_store`, `StoreSettings.task()`; None: computed afresh).
    """
    return {
        "index": index,
        "hash": hash,
        "scenario": scenario.model_dump(mode="json"),
        "out_dir": str(out_dir),
        "uplink": uplink,
    }


def completed_metrics(out_dir: str | Path) -> dict[str, Any] | None:
    """The metrics of a finished run in `out_dir` (metrics.json is written last), or None."""
    from uma.errors import ConfigError
    from uma.paths import read_capped

    path = Path(out_dir) / "metrics.json"
    if not path.exists():
        return None
    try:  # a FIFO or a device left there is no finished run (and would block a plain read)
        data = json.loads(read_capped(path, max_bytes=16 * 2**20, error=ConfigError))
    except (ConfigError, ValueError, RecursionError):
        return None
    return data if isinstance(data, dict) else None


def run_point(task: dict[str, Any]) -> dict[str, Any]:
    """Simulate the task's scenario, write its results; `{index, hash, status, error, metrics}`.

    Scoring runs inline (`metrics.workers: 0`): a sweep's parallelism is across points, and the
    results do not depend on it.
    """
    from uma.atomic import atomic_dir
    from uma.metrics.results import RUN_FILES

    out = Path(task["out_dir"])
    reply: dict[str, Any] = {"index": task["index"], "hash": task["hash"], "error": ""}
    try:
        from uma.config.scenario import Scenario
        from uma.experiments.uplink_store import open_store
        from uma.sim import run_scenario
        from uma.sim.summary import save_run

        data = dict(task["scenario"])
        data["metrics"] = dict(data.get("metrics", {}), workers=0)
        scenario = Scenario.model_validate(data)
        store = open_store(task.get("uplink"))
        metrics = save_run(run_scenario(scenario, uplink=store), out)
    except Exception as err:  # recorded with the point, never lost: the sweep goes on
        message = " ".join(str(err).split()) or type(err).__name__
        reply |= {"status": "failed", "error": f"{type(err).__name__}: {message}", "metrics": {}}
        with contextlib.suppress(Exception), atomic_dir(out, replaceable=RUN_FILES) as staging:
            # The reply still carries the error if this fails; the folder is whole either way.
            (staging / "error.txt").write_text(reply["error"] + "\n", encoding="utf-8")
        return reply
    return reply | {"status": "ok", "metrics": metrics}
