"""Run `uma bench mbc` several times, one process after another, and record each run's model
path per clip: the figures issue #27's speed target is judged on (median over the runs).

    python scripts/model_path_runs.py [--runs N] [--allow-dirty]

writes `docs/results/mbc-speed.json` (as scripts/record_bench.py writes a record: `command`
(the bench's, with the runs and this script), `commit`, `date_utc`, `load_1m`, `duration_s`,
`machine`) whose `result` holds, per run, the
1-minute load before and after and, per clip, `model_path_ms` (wall), `model_path_cpu_ms`,
`stages_ms` and `stages_cpu_ms` as `uma bench mbc --json` printed them. One run's model path
is deterministic work, yet on this 2-core machine the same clip's figure spread 10.8-15.1 ms
over five runs at idle (docs/measured.md): one run is not a median. Every run's other figures
(scores, rates, counts: every key not naming a time or a load) must be the same as the first
run's, else nothing is written (exit 1). Exit 0 recorded; 1 a run failed; 2 bad input.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import record_bench  # noqa: E402  (beside this file)

__all__ = ["main", "figures", "timings"]

NAME = "mbc-speed"
_TIMED = ("model_path_ms", "model_path_cpu_ms", "stages_ms", "stages_cpu_ms")
# A key holding one of these words (between underscores), or ending in "_s", is a time or a
# load: it may differ from run to run.
_TIME_WORDS = {"ms", "cpu", "load", "duration"}


def _timed(key: str) -> bool:
    return bool(_TIME_WORDS & set(key.split("_"))) or key.endswith("_s")


def figures(value):
    """`value` (a bench's JSON) without the keys that name times or loads."""
    if isinstance(value, dict):
        return {key: figures(item) for key, item in value.items() if not _timed(key)}
    if isinstance(value, list):
        return [figures(item) for item in value]
    return value


def timings(result: dict) -> dict:
    """Per clip of `uma bench mbc --json`'s `result`, its model path figures and its kind
    (a real clip, or the face model's own rendering)."""
    return {
        name: {"kind": clip["kind"]} | {key: clip[key] for key in _TIMED}
        for name, clip in result["clips"].items()
    }


def _run_once(argv: list[str]) -> tuple[dict, dict]:
    """One bench run: its result and its load before and after."""
    before = os.getloadavg()[0]
    result = record_bench.run_bench("mbc", argv)
    return result, {"before": round(before, 2), "after": round(os.getloadavg()[0], 2)}


def record(runs: int, allow_dirty: bool = False) -> Path:
    """Run the bench `runs` times, then write and return the record."""
    if runs < 1:
        raise record_bench.RecordError(f"--runs: expected at least 1, got {runs}")
    path = record_bench.result_path(NAME, None)
    commit, dirty = record_bench.tree(allow_dirty)
    argv = [sys.executable, "-m", "uma", "bench", "mbc", "--json", "--quiet"]
    load_before, start = os.getloadavg()[0], time.monotonic()
    first, out = None, []
    for index in range(runs):
        result, load = _run_once(argv)
        if first is None:
            first = figures(result)
        elif figures(result) != first:
            raise RuntimeError(
                f"run {index + 1}: its figures differ from run 1's; nothing recorded"
            )
        out.append({"load_1m": load, "clips": timings(result)})
    # What ran, as a user types it, and how many times (the records' rule: `uma bench ...`).
    command = (
        f"uma bench mbc --json --quiet (x{runs}: python scripts/model_path_runs.py --runs {runs})"
    )
    duration_s = time.monotonic() - start
    doc = record_bench.record_doc(
        command, argv, (commit, dirty), load_before, duration_s, {"runs": out}
    )
    record_bench._write_atomic(path, json.dumps(doc, indent=2) + "\n")
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="model_path_runs.py", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument("--runs", type=int, default=5, help="bench runs (default 5)")
    parser.add_argument("--allow-dirty", action="store_true", help="record from a dirty tree")
    args = parser.parse_args(argv)
    try:
        path = record(args.runs, args.allow_dirty)
    except record_bench.RecordError as exc:
        print(f"model_path_runs: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:
        print(f"model_path_runs: error: {exc}", file=sys.stderr)
        return 1
    print(path.relative_to(record_bench.ROOT))
    return 0


if __name__ == "__main__":
    sys.exit(main())
