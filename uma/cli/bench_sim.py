"""`uma bench sim`: simulation cost against the bare codec and metric work inside it."""

from __future__ import annotations

import argparse

from uma.cli.args import frame_size

__all__ = ["register"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "sim",
        help="whole simulation vs the same libx264 and metric work alone",
        description="Run a scenario (default: the default scenario) for --frames frames, then redo "
        "its codec work (sender encode, engine decode and re-encode, receiver decode) and its "
        "quality metrics alone in the same process, and print both times, their ratio and how "
        "much faster than real time the simulation ran.",
    )
    parser.add_argument("--scenario", metavar="FILE", help="scenario file (default: the default)")
    parser.add_argument("--frames", type=int, default=750, help="frames to simulate (default 750)")
    parser.add_argument("--size", type=frame_size, default=(352, 288), help="cif, qcif or WxH")
    parser.add_argument("--video", metavar="FILE", help="use this video file as the source")
    parser.add_argument(
        "--codec",
        metavar="NAME",
        help="the full-frame codec of the ladder (engine.codec: h264, vp8, av1; default the "
        "scenario's), on its own ladder file",
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from uma.bench.sim import SimBenchConfig, format_table, run_sim_bench
    from uma.cli.cmd_bench import emit
    from uma.codecs import full_frame_names
    from uma.config import load_scenario
    from uma.errors import ConfigError
    from uma.experiments.uplink_store import store_settings

    if args.frames <= 0:
        raise ConfigError(f"--frames: expected a positive integer, got {args.frames}")
    if args.codec is not None and args.codec not in full_frame_names():
        raise ConfigError(
            f"--codec: expected one of {', '.join(full_frame_names())}, got {args.codec!r}"
        )
    scenario = load_scenario(args.scenario).with_seed(args.seed)
    width, height = args.size
    config = SimBenchConfig(
        scenario=scenario,
        frames=args.frames,
        width=width,
        height=height,
        video=args.video,
        codec=args.codec,
        store=store_settings(),
    )
    result = run_sim_bench(config)
    emit(result, format_table(result), as_json=args.json)
    return 0
