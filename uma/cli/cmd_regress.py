"""`uma regress SUITE.yaml`: gate CI on rate and quality metrics against baselines."""

from __future__ import annotations

import argparse

__all__ = ["register"]

HELP = """\
Run the short scenarios a suite lists (or read finished results with --results DIR, where
DIR/<scenario name>/metrics.json is what `uma run --out DIR/<name>` writes) and compare each
gated metric with the suite's baseline file under its tolerance and direction. Prints
scenario, metric, baseline, now, change, tolerance, verdict.

A baseline belongs to a kind of machine as well as to the code: a suite's machine_baselines
maps a machine class (avx512: the CPU has AVX-512F) to its own file, and baseline serves every
other machine; the last line names the file and the class.

--update rewrites this machine's baseline from these results, on purpose, and shows what changed.
Each run's folder under --out is replaced whole. Exit status: 0 every metric within its
tolerance, 1 a regression (a missing metric, a missing metrics.json or a failed run is one),
2 bad input (suite, baseline or scenario files, a metrics.json cut short or unparseable)."""


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.args import workers

    parser = sub.add_parser(
        "regress",
        help="compare metrics with the repository's baselines; exit 1 on a regression",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("suite", metavar="SUITE.yaml", help="suite file")
    parser.add_argument("--results", metavar="DIR", help="read finished results instead of running")
    parser.add_argument("--out", metavar="DIR", help="where runs go (default results/regress)")
    parser.add_argument(
        "--workers", type=workers, default=2, help="worker processes (default 2, at most 64)"
    )
    parser.add_argument("--update", action="store_true", help="rewrite the baseline on purpose")
    parser.set_defaults(func=handle)


def _load(args: argparse.Namespace):
    """(the suite, its scenarios, their names, the baseline or None), each checked."""
    from uma.config import load_scenario
    from uma.errors import ConfigError
    from uma.experiments.machine import machine_class
    from uma.experiments.regress import check_only, load_baseline, load_suite

    if args.workers < 1:
        raise ConfigError(f"--workers: expected a positive integer, got {args.workers}")
    if args.results and args.out is not None:
        raise ConfigError("--results and --out: give one (--results reads, --out runs)")
    suite = load_suite(args.suite, machine_class())
    scenarios = [load_scenario(path) for path in suite.scenarios]
    names = [s.name for s in scenarios]
    if len(set(names)) != len(names):
        raise ConfigError(f"{suite.path} (scenarios): two scenarios share a name: {names}")
    check_only(suite, names)
    baseline = None
    if not args.update or suite.baseline_path.exists():
        baseline = load_baseline(suite.baseline_path)
    return suite, scenarios, names, baseline


def _read_results(folder: str, names: list[str]) -> tuple[dict, list[str]]:
    """(metrics by scenario name, from `folder/<name>/metrics.json`; the failures)."""
    from pathlib import Path

    from uma.errors import ConfigError

    results = Path(folder)
    if not results.is_dir():
        raise ConfigError(f"--results: expected a folder of results, got {str(results)!r}")
    now: dict[str, dict | None] = {}
    failures = []
    for name in names:
        now[name] = _read_metrics(results / name / "metrics.json")
        if now[name] is None:
            failures.append(f"{name}: no {results / name / 'metrics.json'}")
    return now, failures


def _run(args: argparse.Namespace, scenarios: list) -> tuple[dict, list[str]]:
    """(metrics by scenario name, from running each into `--out`; the failures)."""
    from pathlib import Path

    from uma.atomic import prepare_out_dir
    from uma.experiments.executor import LocalExecutor
    from uma.experiments.point import point_task, run_point
    from uma.experiments.spec import scenario_hash
    from uma.metrics.results import RUN_FILES

    out = prepare_out_dir(args.out if args.out is not None else Path("results") / "regress")
    for scenario in scenarios:  # each run's folder is replaced whole: refuse before running
        prepare_out_dir(out / scenario.name, what="--out", replaceable=RUN_FILES)
    tasks = [
        point_task(s, out / s.name, index=i, hash=scenario_hash(s)) for i, s in enumerate(scenarios)
    ]
    executor = LocalExecutor(min(args.workers, len(tasks)))
    try:
        replies = {r["index"]: r for r in executor.map_unordered(run_point, tasks)}
    except BaseException:
        executor.terminate()  # Ctrl-C: end the runs now rather than wait for them
        raise
    finally:
        executor.close()
    now: dict[str, dict | None] = {}
    failures = []
    for i, scenario in enumerate(scenarios):
        reply = replies[i]
        now[scenario.name] = reply["metrics"] if reply["status"] == "ok" else None
        if reply["status"] != "ok":
            failures.append(f"{scenario.name}: the run failed: {reply['error']}")
    return now, failures


def _update(suite, baseline, now: dict, failures: list[str]) -> int:
    """Rewrite the baseline from `now`, showing what changed; 1 (and no write) on a failure."""
    import sys

    from uma.atomic import atomic_write_text
    from uma.errors import ConfigError
    from uma.experiments.regress import baseline_yaml, compare, format_checks

    if failures:
        print("uma regress: baseline not updated", file=sys.stderr)
        return 1
    if baseline is not None:
        try:
            checks = compare(suite, baseline, {k: v for k, v in now.items() if k in baseline})
            print(format_checks(checks))
        except ConfigError as err:
            print(f"(previous baseline incomplete: {err})")
    atomic_write_text(suite.baseline_path, baseline_yaml(suite, now))
    print(
        f"baseline {suite.baseline_path} written (machine class: {suite.machine}; {len(now)} scenarios, "
        f"{sum(len(suite.metrics_of(name)) for name in now)} metrics)"
    )
    return 0


def handle(args: argparse.Namespace) -> int:
    import sys

    from uma.experiments.regress import check_metric_paths, compare, format_checks

    suite, scenarios, names, baseline = _load(args)
    if args.results:
        now, failures = _read_results(args.results, names)
    else:
        now, failures = _run(args, scenarios)
    check_metric_paths(suite, now, baseline=baseline, update=args.update)
    for line in failures:
        print(f"uma regress: {line}", file=sys.stderr)
    if args.update:
        return _update(suite, baseline, now, failures)
    checks = compare(suite, baseline, now)
    print(format_checks(checks))
    bad = sum(check.failed for check in checks)
    print(
        f"{len(checks)} checks, {bad} regressed"
        + (" or missing" if bad else "")
        + f" (baseline {suite.baseline_path.name}, machine class {suite.machine})"
    )
    return 1 if bad or failures else 0


def _read_metrics(path):
    """`uma.metrics.results.read_metrics`: a FIFO, a symlink loop, a file past its cap or
    JSON nested too deep is one line (`ConfigError`), a missing file None."""
    from uma.metrics.results import read_metrics

    return read_metrics(path)
