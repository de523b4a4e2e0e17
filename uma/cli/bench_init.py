"""`uma bench init`: SAABs and its rivals on real faces rendered at known poses."""

from __future__ import annotations

import argparse

__all__ = ["register"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "init",
        help="face-model initialisation: SAABs vs Gauss-Newton, dual annealing, hybrid",
        description="Build test cases from real faces (--faces, ORL layout; --yale, Yale B lighting) "
        "rendered at known random poses, fit each with SAABs, SAABs with illumination "
        "compensation, Gauss-Newton, scipy's dual_annealing (same cost and evaluation budget) "
        "and the hybrid, and print a Table-I-style comparison: MDE per case, median and 95th "
        "percentile MDE, success rate (MDE < 1.5 px at 92x112) and median time. Without shared "
        "data, the built-in astronaut is the template.",
    )
    parser.add_argument(
        "--faces", metavar="DIR", help="ORL-layout folder (default ../shared/data/faces/orl)"
    )
    parser.add_argument(
        "--yale", metavar="DIR", help="Yale B folder (default ../shared/data/faces/yale_b)"
    )
    parser.add_argument("--cases", type=int, default=80, help="number of cases (default 80)")
    parser.add_argument(
        "--cif-frames",
        type=int,
        default=10,
        help="whole CIF talking-head frames to fit too (default 10; 0: none)",
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    import sys
    from pathlib import Path

    from uma.bench.init import InitBenchConfig, run_init_bench
    from uma.bench.init_table import format_table
    from uma.cli.cmd_bench import emit
    from uma.errors import ConfigError
    from uma.paths import shared_data_dir

    if args.seed < 0:
        raise ConfigError(f"--seed: expected a non-negative integer, got {args.seed}")
    if args.cases <= 0:
        raise ConfigError(f"--cases: expected a positive integer, got {args.cases}")
    faces = Path(args.faces) if args.faces else shared_data_dir() / "faces" / "orl"
    yale = Path(args.yale) if args.yale else shared_data_dir() / "faces" / "yale_b"
    for option, path in (("--faces", args.faces), ("--yale", args.yale)):
        if path and not Path(path).is_dir():
            raise ConfigError(f"{option}: expected a folder of face images, got {path!r}")
    bar = None
    if not args.quiet and sys.stderr.isatty():
        from tqdm import tqdm

        bar = tqdm(total=args.cases, unit="case", desc="bench init", file=sys.stderr, leave=False)
    if args.cif_frames < 0:
        raise ConfigError(f"--cif-frames: expected a non-negative integer, got {args.cif_frames}")
    config = InitBenchConfig(
        cases=args.cases, faces=faces, yale=yale, seed=args.seed, cif_frames=args.cif_frames
    )
    try:
        result = run_init_bench(
            config, progress=(lambda done, total: bar.update(1)) if bar else None
        )
    finally:
        if bar is not None:
            bar.close()
    emit(result, format_table(result), as_json=args.json)
    return 0
