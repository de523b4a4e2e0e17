"""`uma bench headline`: H.264 only, switching, and an oracle, on the default and the real commute."""

from __future__ import annotations

import argparse

__all__ = ["register"]

SCENARIOS = ("stockholm-uppsala.yaml", "stockholm-uppsala-real.yaml")


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.args import seconds, workers
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "headline",
        help="what switching to the model-based codec buys, against H.264 and AV1 alone",
        description="Run the default commute (synthetic talking head) and the real one (measured "
        "traces, akiyo looped) with six engines each: h264 (the H.264 ladder only), uma "
        "(switching to the model-based codec), predictive (switching with the coverage map), "
        "oracle (knows the trace), av1 (the AV1 ladder only) and av1+mbc (AV1 with switching), "
        "and print frozen share, displayed fps, PSNR and SSIM over the frame and the face, delay "
        "p95, kbit/s per codec, switches, initialisations, description delivery and the lag "
        "from a handover into GPRS or GSM to the model codec, with the targets.",
    )
    parser.add_argument(
        "--scenario",
        metavar="FILE",
        action="append",
        help="a scenario to run instead of the two (repeat for more)",
    )
    parser.add_argument("--skip-real", action="store_true", help="run only the default scenario")
    parser.add_argument(
        "--duration-s",
        type=float,
        help="simulate only the first this many seconds of each scenario",
    )
    parser.add_argument(
        "--playout",
        choices=("adaptive", "fixed"),
        default="adaptive",
        help="every engine's playout: adaptive (default) or each scenario's own",
    )
    parser.add_argument("--out", metavar="DIR", help="save each run's results under DIR")
    parser.add_argument(
        "--workers",
        type=workers,
        help="run the scenario-engine pairs on this many local worker processes "
        "(default: one after another in this process)",
    )
    parser.add_argument(
        "--scheduler", metavar="ADDRESS", help="run the pairs on a Dask cluster, tcp://host:port"
    )
    parser.add_argument(
        "--timeout", type=seconds, default=10.0, metavar="S", help="seconds to reach the scheduler"
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.bench.headline import HeadlineConfig, format_table, run_headline
    from uma.cli.args import one_executor
    from uma.cli.cmd_bench import bench_executor, emit, progress_printer
    from uma.config import load_scenario
    from uma.errors import ConfigError
    from uma.experiments.uplink_store import store_settings
    from uma.paths import scenarios_dir

    if args.duration_s is not None and not args.duration_s > 0:
        raise ConfigError(f"--duration-s: expected a positive number, got {args.duration_s}")
    one_executor(args)  # --workers, --timeout and --seed are bounded by their parsers
    names = SCENARIOS[:1] if args.skip_real else SCENARIOS
    paths = args.scenario or [scenarios_dir() / name for name in names]
    scenarios = []
    for path in paths:
        scenario = load_scenario(path)
        if args.seed:
            scenario = scenario.with_seed(args.seed)
        if args.duration_s is not None:
            scenario = scenario.model_copy(update={"duration_s": args.duration_s})
        scenarios.append(scenario)
    out_dir = None
    if args.out:
        out_dir = Path(args.out)
        if out_dir.exists() and not out_dir.is_dir():
            raise ConfigError(f"--out: {str(out_dir)!r} is a file, expected a folder")

    progress = progress_printer(args)

    config = HeadlineConfig(
        scenarios=tuple(scenarios), playout=args.playout, out_dir=out_dir, uplink=store_settings()
    )
    with bench_executor(args) as executor:
        result = run_headline(config, progress=progress, executor=executor)
    emit(result, format_table(result), as_json=args.json)
    return 0
