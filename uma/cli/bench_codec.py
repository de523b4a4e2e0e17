"""`uma bench codec`: libx264 rate accuracy per rung, codec speed, metric costs."""

from __future__ import annotations

import argparse

__all__ = ["register"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "codec",
        help="libx264 rate accuracy per ladder rung, encode/decode speed, SSIM and PSNR cost",
        description="Encode a real clip at every rung of codecs/h264.yaml and compare the measured "
        "rate (after the first second) with the target; time libx264 encode and FFmpeg decode; "
        "time SSIM and PSNR on one luma plane.",
    )
    parser.add_argument(
        "--video", metavar="FILE", help="clip (default ../shared/data/faces/video/akiyo.mp4)"
    )
    parser.add_argument("--frames", type=int, default=300, help="frames to use (default 300)")
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.bench.codec import format_table, run_codec_bench
    from uma.cli.cmd_bench import emit
    from uma.errors import ConfigError
    from uma.paths import shared_data_dir

    if args.frames < 30:
        raise ConfigError(f"--frames: expected at least 30, got {args.frames}")
    if args.video and not Path(args.video).is_file():
        raise ConfigError(f"--video: expected an existing video file, got {args.video!r}")
    video = Path(args.video) if args.video else shared_data_dir() / "faces" / "video" / "akiyo.mp4"
    result = run_codec_bench(video=video, frames=args.frames)
    emit(result, format_table(result), as_json=args.json)
    return 0
