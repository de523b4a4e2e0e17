"""`uma bench links`'s scenario on chosen minutes of traces, with uma's controller settings changed.

`python scripts/links_settings.py --case TRACE:OFFSET_S:DURATION_S [--case ...] [--engines
uma,gcc] [--set judge_silence=true ...] [--engine climb=stream ...] [--workers 2] [--json OUT]`
runs, per case and engine,
the Salsify scenario exactly as `uma bench links` builds it (`uma.bench.links.link_task`, seed 0)
on the trace from OFFSET_S for DURATION_S (`route[0].offset_s`), and prints its row (delay p95
and median in ms, unfrozen SSIM in dB, frozen share, utilisation, video kbit/s). `--set` changes
a field of `uma.control.UmaSettings` for the `uma` engine (values are JSON): the controller's
settings that have no scenario key are reached by building the engine's `UmaSettings` with
them, and a `--set` wins over the scenario's key of the same name (before session 29 the
scenario's won: `--set judge_silence=true` and the other `engine.estimator` keys were silently
ignored); the `uma` rows of a run with no `--set` are the bench's to the digit. `--engine` sets a
key of the scenario's `engine` section for every engine (values are JSON; `climb` is the rate
policy's, which every engine follows: docs/rate-control.md, branch rc23). Run from the
repository root with the checkout on `PYTHONPATH` (docs/rate-control.md, branch rc22).
"""

from __future__ import annotations

import argparse
import json
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path


def case_task(trace: str, offset_s: float, duration_s: float, engine: str, engine_keys: dict):
    """The links bench's task for `engine` on `trace` from `offset_s`, with `engine_keys` set."""
    from uma.bench.links import LinksConfig, link_task
    from uma.config import load_scenario

    scenario = load_scenario(Path("scenarios/salsify-tmobile-umts.yaml")).with_seed(0)
    config = LinksConfig(scenario=scenario, traces=(trace,), duration_s=duration_s)
    task = link_task(config, trace, engine, duration_s)
    task["scenario"]["route"][0]["offset_s"] = offset_s
    task["scenario"].setdefault("engine", {}).update(engine_keys)
    return task


def bad_argument(message: str) -> None:
    """One line on stderr naming the bad argument, and exit 2 (the CLI's rule for bad input)."""
    print(f"{Path(sys.argv[0]).name}: error: {message}", file=sys.stderr)
    raise SystemExit(2)


def json_keys(items: list[str]) -> dict:
    """`KEY=JSON` arguments as a mapping."""
    keys = {}
    for item in items:
        key, equals, value = item.partition("=")
        try:
            if not key or not equals:
                raise ValueError("expected KEY=JSON")
            keys[key] = json.loads(value)
        except ValueError as err:
            bad_argument(f"{item!r}: {err}")
    return keys


def add_case_arguments(parser: argparse.ArgumentParser, engines: str) -> None:
    """The options the case scripts share: `--case` (repeated), `--engines`, `--engine KEY=JSON`
    (repeated) and `--workers`."""
    parser.add_argument("--case", action="append", required=True, help="TRACE:OFFSET_S:DURATION_S")
    parser.add_argument("--engines", default=engines)
    parser.add_argument("--engine", action="append", default=[], help="engine KEY=JSON")
    parser.add_argument("--workers", type=int, default=2)


def cases(args: argparse.Namespace) -> list[tuple[str, float, float, str]]:
    """(trace, offset_s, duration_s, engine) for every `--case` and every engine of `--engines`."""
    out = []
    for case in args.case:
        try:
            trace, offset_s, duration_s = case.rsplit(":", 2)
            offset_s, duration_s = float(offset_s), float(duration_s)
        except ValueError:
            bad_argument(f"--case {case!r}: expected TRACE:OFFSET_S:DURATION_S")
        if not Path(trace).is_file():
            bad_argument(f"--case {case!r}: no trace file {trace}")
        if not (offset_s >= 0 and duration_s > 0):
            bad_argument(f"--case {case!r}: expected OFFSET_S >= 0 and DURATION_S > 0")
        out += [(trace, offset_s, duration_s, e) for e in args.engines.split(",")]
    return out


def override_settings(overrides: dict) -> None:
    """Build the `uma` engine's `UmaSettings` with `overrides`, over the keys the engine
    passes from the scenario too (this process only: the script runs each case in a worker)."""
    import uma.engine.rate as rate
    from uma.control.settings import UmaSettings

    rate.UmaSettings = lambda **keys: UmaSettings(**{**keys, **overrides})


def _case_row(job: tuple) -> tuple:
    trace, offset_s, duration_s, engine, overrides, engine_keys = job
    from uma.bench.links import run_link

    if overrides:
        override_settings(overrides)
    task = case_task(trace, offset_s, duration_s, engine, engine_keys)
    return trace, offset_s, duration_s, engine, run_link(task)["row"]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_case_arguments(parser, "uma,gcc")
    parser.add_argument("--set", action="append", default=[], help="UmaSettings FIELD=JSON")
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    overrides, engine_keys = json_keys(args.set), json_keys(args.engine)
    jobs = [(*case, overrides if case[3] == "uma" else {}, engine_keys) for case in cases(args)]
    rows = []
    with ProcessPoolExecutor(args.workers) as pool:
        for trace, offset_s, duration_s, engine, row in pool.map(_case_row, jobs):
            name = Path(trace).stem
            rows.append(dict(trace=name, offset_s=offset_s, duration_s=duration_s, engine=engine))
            rows[-1].update(row)
            print(
                f"{name[:22]:22s} {offset_s:5.0f}+{duration_s:3.0f} {engine:6s} "
                f"p95 {row['delay_p95_ms']:8.0f} median {row['delay_median_ms']:6.0f} "
                f"SSIM unfrozen {row['ssim_db_unfrozen']:6.2f} frozen {row['freeze_ratio']:.4f} "
                f"utilisation {row['utilisation']:.3f} video {row['kbps_video']:.1f} kbit/s",
                flush=True,
            )
    if args.json:
        Path(args.json).write_text(
            json.dumps({"overrides": overrides, "engine": engine_keys, "rows": rows}, indent=1)
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
