"""`uma bench playout`: playout settings replayed exactly on a scenario's recorded runs."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["register"]

MAX_GRID_BYTES = 1 << 20
MAX_SETTINGS = 10_000


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.args import seconds, setting, workers

    parser = sub.add_parser(
        "playout",
        help="playout settings replayed exactly on a scenario's recorded runs",
        description="Run the scenario once per seed with its own playout, recording the frames "
        "the receiver decoded, then replay each playout setting (receiver.adaptive keys) on "
        "every recording: exactly the display a full run with that setting gives, in a "
        "fraction of a second. Prints per setting the median delay p95 and median and frozen "
        "share over the seeds and the paired-median change against the scenario's own "
        "playout. Default scenario: the default commute as the uma engine runs it "
        "(scenarios/stockholm-uppsala.yaml, adaptive playout).",
    )
    parser.add_argument("--scenario", metavar="FILE", help="scenario file (default: the commute)")
    parser.add_argument(
        "--seeds", metavar="LIST", help="comma-separated seeds (default: the scenario's own)"
    )
    parser.add_argument(
        "--set",
        dest="set_",
        type=setting,
        metavar="KEY=VALUE",
        action="append",
        default=[],
        help="a receiver.adaptive key and value (repeat for more keys; one setting, or added "
        "to every setting of --grid)",
    )
    parser.add_argument(
        "--grid",
        metavar="FILE.yaml",
        help="a YAML mapping of receiver.adaptive keys to a value or a list of values: every "
        "combination is a setting",
    )
    parser.add_argument("--workers", type=workers, help="local worker processes (default: none)")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="a Dask scheduler, tcp://host:port")
    parser.add_argument(
        "--timeout", type=seconds, default=10.0, metavar="S", help="seconds to reach the scheduler"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object on stdout only")
    parser.add_argument("--quiet", action="store_true", help="no progress output on stderr")
    parser.set_defaults(func=handle)


def _seeds(text: str | None, default: int) -> tuple[int, ...]:
    from uma.cli.args import seed
    from uma.errors import ConfigError

    if text is None:
        return (default,)
    out = []
    for part in text.split(","):
        try:
            out.append(seed(part.strip()))
        except argparse.ArgumentTypeError as err:
            raise ConfigError(f"--seeds: {err}") from None
    if len(set(out)) != len(out):
        raise ConfigError(f"--seeds: a seed given twice in {text!r}")
    return tuple(out)


def _pairs(items: list[tuple[str, str]]) -> dict[str, Any]:
    """`--set KEY=VALUE` pairs (`uma.cli.args.setting`), the key a receiver.adaptive one; a
    value reads as YAML (`0.5`, `true`)."""
    from uma.cli.args import setting_value

    return {key.removeprefix("receiver.adaptive."): setting_value(key, text) for key, text in items}


def _grid(path: str) -> dict[str, Any]:
    """The grid file: a mapping of keys to a value or a list of values."""
    import yaml

    from uma.errors import ConfigError
    from uma.paths import read_capped

    data = read_capped(path, max_bytes=MAX_GRID_BYTES, error=ConfigError, what="grid file")
    try:
        grid = yaml.safe_load(data.decode("utf-8"))
    except (yaml.YAMLError, UnicodeDecodeError) as err:
        raise ConfigError(f"--grid {path}: not YAML ({str(err).splitlines()[0]})") from None
    if not isinstance(grid, dict) or not grid:
        raise ConfigError(f"--grid {path}: expected a mapping of receiver.adaptive keys")
    out = {}
    for key, values in grid.items():
        if isinstance(values, list) and not values:
            raise ConfigError(f"--grid {path}: {key}: an empty list of values")
        out[str(key).removeprefix("receiver.adaptive.")] = values
    return out


def _config(args: argparse.Namespace):
    """The bench's configuration from the arguments; bad input is one ConfigError line."""
    from uma.bench.headline import engine_scenario
    from uma.bench.playout import PlayoutBenchConfig, grid_settings
    from uma.config import load_scenario
    from uma.errors import ConfigError

    if args.scenario is not None:
        scenario = load_scenario(args.scenario)
    else:
        scenario = engine_scenario(load_scenario(), "uma")
    seeds = _seeds(args.seeds, scenario.seed)
    fixed = _pairs(args.set_)
    settings = grid_settings(_grid(args.grid), fixed) if args.grid else [fixed] if fixed else []
    if len(settings) > MAX_SETTINGS:
        raise ConfigError(f"--grid: {len(settings)} settings, above the maximum {MAX_SETTINGS}")
    where = "--grid" if args.grid else "--set"
    try:
        return PlayoutBenchConfig(scenario=scenario, seeds=seeds, settings=tuple(settings))
    except ValueError as err:
        raise ConfigError(f"{where}: {err}") from None


def handle(args: argparse.Namespace) -> int:

    from uma.bench.playout import format_table, run_playout_bench
    from uma.cli.args import one_executor
    from uma.cli.cmd_bench import bench_executor, emit, progress_printer

    one_executor(args)
    config = _config(args)

    progress = progress_printer(args)

    with bench_executor(args) as executor:
        result = run_playout_bench(config, executor=executor, progress=progress)
    emit(result, format_table(result), as_json=args.json)
    return 0
