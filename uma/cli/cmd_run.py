"""`uma run [SCENARIO.yaml]`: simulate one scenario and write its results."""

from __future__ import annotations

import argparse
import sys

__all__ = ["register"]

HELP = """\
Simulate one scenario: a talking-head conference streamed through the UMA engine to a
mobile receiver whose downlink follows the scenario's route (a chain of bandwidth traces
across WLAN, 3G, GPRS, GSM). Without SCENARIO, runs scenarios/stockholm-uppsala.yaml.

Writes results/<scenario>/ (or --out DIR): metrics.json (aggregates), frames.csv (one row
per displayed frame), events.csv (rung switches, handovers, keyframe requests) and the
resolved scenario.yaml that repeats the run (--set values included); with --report also
timeline.png (see `uma report`). The folder is replaced whole: after a failure or a kill it
holds the earlier run whole or this one whole, never a mix; a folder holding other files is
refused.
Exit status: 0 done, 2 bad input."""


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.args import seed, setting

    parser = sub.add_parser(
        "run",
        help="simulate a scenario (default: Stockholm to Uppsala) and write its results",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("scenario", nargs="?", metavar="SCENARIO.yaml", help="scenario file")
    parser.add_argument("--out", metavar="DIR", help="results folder (default results/<scenario>)")
    parser.add_argument("--seed", type=seed, help="random seed, overriding the scenario's")
    parser.add_argument(
        "--set", type=setting, action="append", default=[], metavar="KEY=VALUE",
        help="a scenario key's value for this run, read as YAML, as an experiment's grid names "
        "it (engine.mbc.refresh.enabled=true, route[1].trace=x.csv; a relative path from "
        "here); repeatable",
    )  # fmt: skip
    parser.add_argument("--quiet", action="store_true", help="no progress bar or summary")
    parser.add_argument(
        "--report", action="store_true", help="draw timeline.png in the results folder too"
    )
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.atomic import prepare_out_dir
    from uma.errors import ConfigError

    scenario = _scenario(args.scenario, args.set)
    if args.seed is not None:
        if args.seed < 0:
            raise ConfigError(f"--seed: expected a non-negative integer, got {args.seed}")
        scenario = scenario.with_seed(args.seed)
    from uma.metrics.results import RUN_FILES

    # Checked before the simulation: the folder is replaced whole, so it may hold only results.
    out_dir = prepare_out_dir(
        args.out if args.out is not None else Path("results") / scenario.name, replaceable=RUN_FILES
    )
    from uma.sim import run_scenario  # after the checks: a refusal does not wait for the kernels
    from uma.sim.summary import format_summary, save_run

    bar = None
    if not args.quiet and sys.stderr.isatty():
        from tqdm import tqdm

        bar = tqdm(unit="frame", desc=scenario.name, file=sys.stderr, leave=False)

        def progress(done: int, total: int) -> None:
            bar.total = total
            bar.update(done - bar.n)

    try:
        result = run_scenario(scenario, progress=progress if bar else None)
    finally:
        if bar is not None:
            bar.close()
    metrics = save_run(result, out_dir)
    if not args.quiet:
        print(format_summary(metrics, out_dir))
    if args.report:
        from uma.report.timeline import draw_timeline

        picture = draw_timeline(out_dir)
        if not args.quiet:
            print(f"  timeline  {picture}")
    return 0


def _scenario(path, settings: list[tuple[str, str]]):
    """The scenario at `path` (the default one if None) with the `--set` values applied,
    validated as the file is; a bad key or value is one `ConfigError` naming it."""
    from uma.config import load_scenario

    if not settings:
        return load_scenario(path)
    from uma.api.overrides import resolve_scenario
    from uma.cli.args import setting_value
    from uma.config.load import default_scenario_path

    values = [(key, setting_value(key, text)) for key, text in settings]
    return resolve_scenario(path or default_scenario_path(), values, origin="--set")
