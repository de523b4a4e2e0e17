"""`uma bench NAME`: benchmarks discovered from `uma/cli/bench_*.py`.

Each `bench_NAME.py` defines `register(subparsers)` like a top-level command. Its handler prints
a readable table, or with `--json` one JSON object on stdout and nothing else (see `emit`).
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["register", "emit", "add_common_arguments", "bench_executor", "progress_printer"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli import _command_modules

    parser = sub.add_parser(
        "bench",
        help="benchmarks that measure speed and accuracy targets side by side",
        description="Benchmarks. Each compares methods in one process, so ratios hold on a noisy "
        "machine. Add --json for one JSON object on stdout.",
    )
    bench_sub = parser.add_subparsers(dest="bench", metavar="NAME")
    for name in _command_modules("bench_"):
        importlib.import_module(f"uma.cli.{name}").register(bench_sub)
    parser.set_defaults(func=lambda args: (parser.print_help(), 2)[1])


def add_common_arguments(parser: argparse.ArgumentParser) -> None:
    """`--json`, `--seed` and `--quiet`, shared by every benchmark."""
    parser.add_argument("--json", action="store_true", help="print one JSON object on stdout only")
    from uma.cli.args import seed

    parser.add_argument("--seed", type=seed, default=0, help="random seed (default 0)")
    parser.add_argument("--quiet", action="store_true", help="no progress output on stderr")


def emit(result: dict[str, Any], table: str, *, as_json: bool) -> None:
    """Print `result` as JSON, or the readable `table`."""
    if as_json:
        json.dump(result, sys.stdout, sort_keys=False)
        sys.stdout.write("\n")
    else:
        sys.stdout.write(table.rstrip("\n") + "\n")


def progress_printer(args: argparse.Namespace) -> Callable[[str], None]:
    """Progress lines on stderr, unless `--quiet` or `--json`."""

    def progress(line: str) -> None:
        if not args.quiet and not args.json:
            print(line, file=sys.stderr, flush=True)

    return progress


@contextmanager
def bench_executor(args: argparse.Namespace) -> Iterator[Any]:
    """The sweep executor `--workers` or `--scheduler` ask for (None: run in this process),
    closed when the bench is done."""
    executor = None
    if args.workers is not None or args.scheduler:
        from uma.experiments import make_executor

        executor = make_executor(
            workers=args.workers, scheduler=args.scheduler, timeout_s=args.timeout
        )
    try:
        yield executor
    finally:
        if executor is not None:
            executor.close()
