"""`uma bench quality`: uma's SSIM against scikit-image's on real coded frames, and its cost."""

from __future__ import annotations

import argparse

__all__ = ["register"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "quality",
        help="SSIM and PSNR against scikit-image on real coded frames, and their cost",
        description="Code real clips at every rung of codecs/h264.yaml, decode and upscale them "
        "as the receiver shows them, and compare uma's PSNR and SSIM (whole frame and face box) "
        "with scikit-image's on every pair; then time both on one CIF luma plane, side by side.",
    )
    parser.add_argument(
        "--video",
        metavar="FILE",
        action="append",
        help="clip to use, repeatable (default: akiyo and carphone from ../shared/data)",
    )
    parser.add_argument("--pairs", type=int, default=200, help="frame pairs (default 200)")
    parser.add_argument("--repeats", type=int, default=100, help="timing repeats (default 100)")
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.bench.quality import format_table, run_quality_bench
    from uma.cli.cmd_bench import emit
    from uma.errors import ConfigError
    from uma.paths import shared_data_dir

    if args.pairs < 1:
        raise ConfigError(f"--pairs: expected a positive integer, got {args.pairs}")
    if args.repeats < 1:
        raise ConfigError(f"--repeats: expected a positive integer, got {args.repeats}")
    if args.video:
        clips = {Path(v).stem: Path(v) for v in args.video}
    else:
        folder = shared_data_dir() / "faces" / "video"
        clips = {"akiyo": folder / "akiyo.mp4", "carphone": folder / "carphone_qcif.mp4"}
    for path in clips.values():
        if not path.is_file():
            raise ConfigError(f"--video: expected an existing video file, got {str(path)!r}")
    result = run_quality_bench(clips=clips, pairs=args.pairs, repeats=args.repeats)
    emit(result, format_table(result), as_json=args.json)
    return 0
