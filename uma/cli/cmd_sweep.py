"""`uma sweep EXPERIMENT.yaml`: run a grid of scenarios on local processes or a Dask cluster."""

from __future__ import annotations

import argparse
import signal
import sys

__all__ = ["register", "Terminated"]


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the main thread is, so the sweep stops as on Ctrl-C."""


def _terminated(signum, frame) -> None:
    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # a second SIGTERM must not cut the cleanup
    raise Terminated


HELP = """\
Run every point of an experiment: a base scenario and a grid over its keys (see
uma/experiments/spec.py, or the README). Points run on local worker processes (--workers,
default 2), or on a Dask cluster when --scheduler gives its address (tcp://host:port; the
workers must see the same files and the --out folder).

Writes OUT/sweep.csv and OUT/sweep.parquet (one row per run: the grid's keys, a status, every
metric) and OUT/points/<hash>/ per run, each folder whole. Rerunning skips points already
complete (keyed by the hash of the resolved scenario and of the contents of every file it
reads); a failed point is recorded with its error and the others go on. The table is written
before the first point runs and kept current: a point not run yet has status `missing`. Ctrl-C
or SIGTERM ends the workers, writes the table of what is done and exits 130 or 143; workers
also end when this process is killed. A grid over 10,000 runs, or with a value given twice,
is refused. Exit status: 0 all points ran, 1 some point failed, 2 bad input."""


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.args import seconds, workers

    parser = sub.add_parser(
        "sweep",
        help="run a grid of scenarios (local processes or Dask), one table of results",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("experiment", metavar="EXPERIMENT.yaml", help="experiment file")
    parser.add_argument(
        "--workers", type=workers, help="local worker processes (default 2, at most 64)"
    )
    parser.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler, tcp://host:port")
    parser.add_argument(
        "--timeout", type=seconds, default=10.0, metavar="S", help="seconds to reach the scheduler"
    )
    parser.add_argument("--out", metavar="DIR", help="results folder (default results/<name>)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar or summary")
    parser.set_defaults(func=handle)


def _progress_bar(args: argparse.Namespace, experiment):
    """(a progress bar on a terminal's stderr, its callback), or (None, None)."""
    if args.quiet or not sys.stderr.isatty():
        return None, None
    from tqdm import tqdm

    bar = tqdm(total=len(experiment.points), unit="point", desc=experiment.name, file=sys.stderr)

    def progress(done: int, total: int) -> None:
        bar.update(done - bar.n)

    return bar, progress


def _print_summary(experiment, result) -> None:
    print(
        f"sweep {experiment.name}: {len(result.rows)} points, {result.ran} run, "
        f"{result.skipped} already complete, {result.failed} failed"
        + (f", {result.missing} not run" if result.missing else "")
        + f"\n  table    {result.csv_path} and {result.parquet_path.name}"
    )
    for row in result.rows:
        if row["status"] == "failed":
            print(f"  failed   point {row['point']} ({row['hash']}): {row['error']}")


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.interrupt import loading

    with loading():  # nothing to clean up yet: Ctrl-C exits at once, even inside an import
        from uma.cli.args import one_executor
        from uma.experiments import load_experiment, make_executor, run_sweep
        from uma.experiments.sweep import check_sweep_out
        from uma.experiments.uplink_store import store_settings

        one_executor(args)  # --workers is bounded by its parser
        experiment = load_experiment(args.experiment)
        out_dir = check_sweep_out(
            args.out if args.out is not None else Path("results") / experiment.name
        )
        uplink = store_settings()  # a bad UMA_CACHE_MB is refused before any worker starts
    executor = make_executor(workers=args.workers, scheduler=args.scheduler, timeout_s=args.timeout)

    bar, progress = _progress_bar(args, experiment)
    import threading

    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _terminated) if main_thread else None
    try:
        result = run_sweep(experiment, out_dir, executor, progress=progress, uplink=uplink)
    except KeyboardInterrupt as err:
        if main_thread:
            signal.signal(signal.SIGTERM, signal.SIG_IGN)  # Ctrl-C then SIGTERM: one is enough
        executor.terminate()
        if bar is not None:
            bar.close()
        what = "SIGTERM" if isinstance(err, Terminated) else "Ctrl-C"
        print(
            f"uma sweep: interrupted ({what}); {out_dir / 'sweep.csv'} lists the points not "
            f"run as missing; run the sweep again to finish them",
            file=sys.stderr,
        )
        return 143 if isinstance(err, Terminated) else 130
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)
        executor.close()
        if bar is not None:
            bar.close()
    if not args.quiet:
        _print_summary(experiment, result)
    return 1 if result.failed or result.missing else 0
