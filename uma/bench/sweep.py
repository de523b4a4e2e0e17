"""`uma bench sweep`: the same 2 x 3 x 2 sweep on one worker process and on two.

Units: seconds of wall clock. The grid is `engine.policy` (throughput, oracle) x
`receiver.playout_delay_ms` (150, 300, 600) x two seeds (`repeat: 2` from `--seed`) over a base scenario cut
to `seconds` of simulated time. Each timing covers starting the worker processes, every run,
and writing the table, into a fresh folder (nothing is skipped as already complete); the two
tables must be identical, or the bench fails.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Any

__all__ = ["run_sweep_bench", "format_table"]

GRID = {
    "engine.policy": ["throughput", "oracle"],
    "receiver.playout_delay_ms": [150, 300, 600],
}


def _experiment_yaml(base: Path, seconds: float, seed: int) -> str:
    import yaml

    data = {
        "name": "bench-sweep",
        "base": str(base.resolve()),
        "set": {"duration_s": float(seconds), "seed": int(seed)},
        "grid": GRID,
        "repeat": 2,
    }
    return yaml.safe_dump(data, sort_keys=False)


def run_sweep_bench(
    *, scenario: Path, seconds: float, seed: int = 0, workers: tuple[int, int] = (1, 2)
) -> dict[str, Any]:
    """Time the sweep on `workers[0]` and on `workers[1]` local processes (seeds seed, seed + 1)."""
    from uma.errors import RunError
    from uma.experiments import LocalExecutor, load_experiment, run_sweep

    times: list[float] = []
    tables: list[bytes] = []
    with tempfile.TemporaryDirectory(prefix="uma-bench-sweep-") as folder:
        path = Path(folder) / "experiment.yaml"
        path.write_text(_experiment_yaml(scenario, seconds, seed), encoding="utf-8")
        experiment = load_experiment(path)
        for count in workers:
            out = Path(folder) / f"out-{count}"
            start = time.perf_counter()
            executor = LocalExecutor(count)
            try:
                result = run_sweep(experiment, out, executor)
            finally:
                executor.close()
            times.append(time.perf_counter() - start)
            if result.failed:
                bad = next(r for r in result.rows if r["status"] != "ok")
                raise RunError(f"bench sweep: point {bad['point']} failed: {bad['error']}")
            tables.append(result.csv_path.read_bytes())
    if tables[0] != tables[1]:
        raise RunError("bench sweep: one and two workers gave different tables")
    return {
        "points": len(experiment.points),
        "seconds_per_run": float(seconds),
        "workers": list(workers),
        "t1_s": round(times[0], 3),
        "t2_s": round(times[1], 3),
        "speedup": round(times[0] / times[1], 3),
        "identical": True,
    }


def format_table(result: dict[str, Any]) -> str:
    return "\n".join(
        [
            f"uma bench sweep: {result['points']} points (2 policies x 3 playout delays x 2 seeds),"
            f" {result['seconds_per_run']:g} s of simulation each",
            f"  1 worker   {result['t1_s']:8.2f} s",
            f"  2 workers  {result['t2_s']:8.2f} s",
            f"  speed-up   {result['speedup']:8.2f}x   (tables identical)",
        ]
    )
