"""`uma bench links`: the Salsify setting on every measured trace, engine beside engine."""

from __future__ import annotations

import argparse

__all__ = ["register"]

DEFAULT_PUBLISHED = "published/salsify-nsdi18.csv"  # under ../shared/data


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.args import seconds, workers
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "links",
        help="the Salsify setting on many measured traces, every engine, with a plot",
        description="Run scenarios/salsify-tmobile-umts.yaml (CIF talking head, adaptive "
        "playout) on each trace with every engine (uma, gcc, webrtc = aiortc's estimator, oracle) "
        "and print delay p95 and median, SSIM dB, frozen share, kbit/s, sent over capacity and "
        "the keyframes' share of the bits per trace, the published figures where known, and "
        "the median over the traces. Default traces: the Mahimahi, HSDPA, NYU-METS, "
        "Pensieve-cooked, 5G and WiFi/cellular traces under ../shared/data/traces.",
    )
    parser.add_argument(
        "--trace", metavar="FILE", nargs="+", help="trace files (any format uma reads)"
    )
    parser.add_argument(
        "--duration",
        "--duration-s",
        dest="duration_s",
        type=float,
        default=300.0,
        help="simulate the first this many seconds of each trace (default 300)",
    )
    parser.add_argument("--plot", metavar="PNG", help="write the delay-SSIM plot here")
    parser.add_argument(
        "--loop",
        action="store_true",
        help="instead of the simulation: the rate controllers (uma, gcc, webrtc, oracle) in a "
        "pure closed loop (no codec), on the tuning and held-out traces (or the --trace files)",
    )
    parser.add_argument(
        "--published",
        metavar="FILE",
        help=f"CSV of published figures (default: ../shared/data/{DEFAULT_PUBLISHED})",
    )
    parser.add_argument("--workers", type=workers, help="local worker processes (default: none)")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="a Dask scheduler, tcp://host:port")
    parser.add_argument(
        "--timeout", type=seconds, default=10.0, metavar="S", help="seconds to reach the scheduler"
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def _check_numbers(args: argparse.Namespace) -> None:
    from uma.cli.args import one_executor
    from uma.errors import ConfigError

    if not args.duration_s > 0:
        raise ConfigError(f"--duration: expected a positive number of s, got {args.duration_s}")
    one_executor(args)


def _traces(args: argparse.Namespace) -> dict[str, float]:
    """Each trace file (resolved) -> its duration in s; a bad file is one line, exit 2."""
    from pathlib import Path

    from uma.bench.links import default_traces, trace_label
    from uma.errors import ConfigError
    from uma.paths import shared_data_dir
    from uma.traces import read_trace

    if args.trace:
        paths = [Path(p) for p in args.trace]
    else:
        paths = default_traces(shared_data_dir() / "traces")
        if not paths:
            raise ConfigError("--trace: no traces given and none under ../shared/data/traces")
    durations: dict[str, float] = {}
    labels: dict[str, str] = {}
    for path in paths:
        if not path.is_file():
            raise ConfigError(f"--trace: expected an existing trace file, got {str(path)!r}")
        resolved = str(path.resolve())
        label = trace_label(resolved)
        if label in labels and labels[label] != resolved:
            raise ConfigError(f"--trace: two traces named {label!r}: {labels[label]}, {resolved}")
        labels[label] = resolved
        durations[resolved] = float(read_trace(resolved).duration_s)  # TraceError: exit 2
    return durations


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.bench.links import LinksConfig, run_links
    from uma.bench.links_table import format_table, save_plot
    from uma.cli.cmd_bench import bench_executor, emit, progress_printer
    from uma.config import load_scenario
    from uma.errors import ConfigError
    from uma.paths import scenarios_dir, shared_data_dir

    _check_numbers(args)
    if args.published is not None and not Path(args.published).is_file():
        raise ConfigError(f"--published: expected a CSV file, got {args.published!r}")
    published = Path(args.published or shared_data_dir() / DEFAULT_PUBLISHED)
    if published.is_file():
        from uma.bench.published import read_published

        read_published(published)  # a malformed file is exit 2 before anything runs
    durations = _traces(args)
    if args.loop:
        return _loop(args, list(durations))
    scenario = load_scenario(scenarios_dir() / "salsify-tmobile-umts.yaml").with_seed(args.seed)
    config = LinksConfig(
        scenario=scenario,
        traces=tuple(durations),
        duration_s=args.duration_s,
        published_file=str(published) if published.is_file() else None,
    )

    progress = progress_printer(args)

    with bench_executor(args) as executor:
        result = run_links(
            config, trace_durations_s=durations, executor=executor, progress=progress
        )
    if args.plot:
        save_plot(result, Path(args.plot))
    emit(result, format_table(result), as_json=args.json)
    return 0


def _loop(args: argparse.Namespace, given: list[str]) -> int:
    """`--loop`: the controllers in the pure closed loop (uma/bench/links_loop.py)."""
    from pathlib import Path

    from uma.bench.links_loop import LoopSettings
    from uma.bench.links_split import HELD_OUT, TUNING, evaluate, format_loop_table
    from uma.cli.cmd_bench import emit, progress_printer
    from uma.paths import shared_data_dir

    progress = progress_printer(args)

    settings = LoopSettings(duration_s=args.duration_s)
    if args.trace:
        sets = {"given": [Path(p) for p in given]}
    else:
        root = shared_data_dir() / "traces"
        sets = {"tuning": [root / p for p in TUNING], "held_out": [root / p for p in HELD_OUT]}
    results = {name: evaluate(paths, settings, progress=progress) for name, paths in sets.items()}
    emit({"loop": results}, format_loop_table(results), as_json=args.json)
    return 0
