"""`uma bench sweep`: a 2 x 3 x 2 sweep on one and on two worker processes, and the speed-up."""

from __future__ import annotations

import argparse

__all__ = ["register"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "sweep",
        help="the same small sweep on one and on two worker processes",
        description="Run a 2 x 3 x 2 grid (engine.policy x receiver.playout_delay_ms x 2 seeds) "
        "of short runs of a scenario (default: the default scenario) on one worker process, "
        "then on two, and print both times and the speed-up. The tables must be identical.",
    )
    parser.add_argument("--scenario", metavar="FILE", help="base scenario (default: the default)")
    parser.add_argument(
        "--seconds", type=float, default=6.0, help="simulated seconds per run (default 6)"
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.bench.sweep import format_table, run_sweep_bench
    from uma.cli.cmd_bench import emit
    from uma.config import default_scenario_path, load_scenario
    from uma.errors import ConfigError

    if not args.seconds > 0:
        raise ConfigError(f"--seconds: expected a positive number, got {args.seconds}")
    path = Path(args.scenario) if args.scenario else default_scenario_path()
    load_scenario(path)  # bad input is exit 2 before any worker starts
    result = run_sweep_bench(scenario=path, seconds=args.seconds, seed=args.seed)
    emit(result, format_table(result), as_json=args.json)
    return 0
