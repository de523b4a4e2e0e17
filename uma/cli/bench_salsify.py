"""`uma bench salsify`: uma's H.264 path on Salsify's T-Mobile UMTS trace beside Salsify's figures."""

from __future__ import annotations

import argparse

__all__ = ["register"]

DEFAULT_TRACE = "traces/mahimahi/TMobile-UMTS-driving.down"  # under ../shared/data
DEFAULT_PUBLISHED = "published/salsify-nsdi18.csv"  # under ../shared/data


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "salsify",
        help="uma and WebRTC estimators on Salsify's trace, beside Salsify's published figures",
        description="Run scenarios/salsify-tmobile-umts.yaml with engine.estimator uma and webrtc "
        "(and the default scenario with both), and print delay p95 and SSIM in dB beside the "
        "figures published for the same trace (Salsify, NSDI 2018, per trace), with the targets. "
        "On another trace the scenario is named after that trace and only the figures "
        "published for it are printed (none if none were).",
    )
    parser.add_argument(
        "--published",
        metavar="FILE",
        help="CSV of published figures per trace and system "
        f"(default: ../shared/data/{DEFAULT_PUBLISHED} if present)",
    )
    parser.add_argument(
        "--trace",
        metavar="FILE",
        help=f"Mahimahi downlink trace (default: ../shared/data/{DEFAULT_TRACE})",
    )
    parser.add_argument("--scenario", metavar="FILE", help="scenario (default: the Salsify one)")
    parser.add_argument(
        "--frames",
        type=int,
        help="frames to simulate (default: the whole trace at the source's rate)",
    )
    parser.add_argument(
        "--clip-frames",
        type=int,
        default=250,
        help="source frames prepared and looped (default 250)",
    )
    parser.add_argument(
        "--skip-default", action="store_true", help="do not also run the default scenario"
    )
    parser.add_argument(
        "--estimators",
        metavar="KINDS",
        default="uma,gcc,webrtc",
        help="comma-separated engine.estimator kinds to run (uma and gcc at least; "
        "default uma,gcc,webrtc); oracle adds the oracle policy, which reads the capacity",
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.bench.salsify import SalsifyBenchConfig, format_table, run_salsify_bench
    from uma.cli.cmd_bench import emit
    from uma.config import load_scenario
    from uma.errors import ConfigError
    from uma.paths import scenarios_dir, shared_data_dir

    for name in ("frames", "clip_frames"):
        value = getattr(args, name)
        if value is not None and value <= 0:
            raise ConfigError(
                f"--{name.replace('_', '-')}: expected a positive integer, got {value}"
            )
    if args.seed < 0:
        raise ConfigError(f"--seed: expected a non-negative integer, got {args.seed}")
    trace = Path(args.trace) if args.trace else shared_data_dir() / DEFAULT_TRACE
    if not trace.is_file():
        raise ConfigError(f"--trace: expected an existing Mahimahi trace file, got {str(trace)!r}")
    from uma.bench.published import published_for

    if args.published is not None and not Path(args.published).is_file():
        raise ConfigError(f"--published: expected a CSV file, got {args.published!r}")
    published_file = args.published or shared_data_dir() / DEFAULT_PUBLISHED
    published = published_for(trace, published_file)  # a malformed file is exit 2 now
    scenario_path = args.scenario or scenarios_dir() / "salsify-tmobile-umts.yaml"
    scenario = load_scenario(scenario_path).with_seed(args.seed)
    default = None if args.skip_default else load_scenario(None).with_seed(args.seed)
    from uma.bench.salsify import BASELINE, KINDS

    kinds = tuple(k.strip() for k in args.estimators.split(",") if k.strip())
    if not set(kinds) <= set(KINDS) or not {"uma", BASELINE} <= set(kinds):
        raise ConfigError(
            f"--estimators: expected kinds among {', '.join(KINDS)} including uma "
            f"and {BASELINE}, got {args.estimators!r}"
        )
    config = SalsifyBenchConfig(
        estimators=kinds,
        scenario=scenario,
        trace=str(trace.resolve()),
        frames=args.frames,
        clip_frames=args.clip_frames,
        default_scenario=default,
        published=published,
        published_file=str(published_file) if Path(published_file).is_file() else None,
    )
    result = run_salsify_bench(config)
    emit(result, format_table(result), as_json=args.json)
    return 0
