"""`uma bench bound`: the least delay each scenario's link allows any engine."""

from __future__ import annotations

import argparse

__all__ = ["register"]

# Scenarios under scenarios/ that the bench takes by default; those whose data is absent are left out.
DEFAULT_SCENARIOS = (
    "stockholm-uppsala.yaml",
    "stockholm-uppsala-real.yaml",
    "salsify-tmobile-umts.yaml",
)


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.args import seed

    parser = sub.add_parser(
        "bound",
        help="the least capture-to-display delay each scenario's link allows any engine",
        description="For every frame of each scenario, the least delay (capture to the first "
        "display of it or a newer frame, as the simulation counts it) that any engine, rate "
        "control and playout could give it: a packet started at the frame's capture, alone on "
        "the scenario's downlink. Prints the p95 and median of those bounds per packet size; a "
        "delay target below the p95 bound cannot be met on that scenario. Default scenarios: "
        "the default commute, the real-video commute and Salsify's (those whose data exists).",
    )
    parser.add_argument("--scenario", metavar="FILE", nargs="+", help="scenario files")
    parser.add_argument(
        "--packet-bytes",
        metavar="SIZES",
        default=",".join(str(b) for b in (40, 120, 1200)),
        help="comma-separated packet sizes in bytes, header included (default 40,120,1200)",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object on stdout only")
    parser.add_argument(
        "--seed", type=seed, help="random seed of modelled links (default: each scenario's own)"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress output on stderr")
    parser.set_defaults(func=handle)


def _packet_bytes(text: str) -> tuple[int, ...]:
    from uma.errors import ConfigError

    sizes = []
    for part in text.split(","):
        part = part.strip()
        if not part.isdigit() or not 1 <= int(part) <= 65535:
            raise ConfigError(
                f"--packet-bytes: expected comma-separated integers from 1 to 65535, got {text!r}"
            )
        sizes.append(int(part))
    return tuple(dict.fromkeys(sizes))


def _scenarios(args: argparse.Namespace) -> list:
    import sys
    from pathlib import Path

    from uma.config import load_scenario
    from uma.errors import ConfigError
    from uma.paths import scenarios_dir

    if args.scenario:
        paths = [Path(p) for p in args.scenario]
        for path in paths:
            if not path.is_file():
                raise ConfigError(
                    f"--scenario: expected an existing scenario file, got {str(path)!r}"
                )
        scenarios = [load_scenario(path) for path in paths]  # bad YAML: exit 2
    else:
        scenarios = []
        for name in DEFAULT_SCENARIOS:
            try:
                scenarios.append(load_scenario(scenarios_dir() / name))
            except ConfigError as err:  # a scenario on ../shared/data without it
                if not args.quiet and not args.json:
                    print(f"left out {name}: {err}", file=sys.stderr)
    if args.seed is not None:
        scenarios = [s.with_seed(args.seed) for s in scenarios]
    names = [s.name for s in scenarios]
    if len(set(names)) != len(names):
        raise ConfigError(f"--scenario: two scenarios share a name: {', '.join(names)}")
    return scenarios


def handle(args: argparse.Namespace) -> int:
    from uma.bench.bound import BoundConfig, format_table, run_bound
    from uma.cli.cmd_bench import emit

    sizes = _packet_bytes(args.packet_bytes)
    config = BoundConfig(scenarios=tuple(_scenarios(args)), packet_bytes=sizes)
    result = run_bound(config)
    emit(result, format_table(result), as_json=args.json)
    return 0
