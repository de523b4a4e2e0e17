"""`uma bench mbc`: the model-based codec on the talking head, akiyo and carphone, or a clip."""

from __future__ import annotations

import argparse

__all__ = ["register"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "mbc",
        help="model-based codec: track, code, decode and render a clip; rates, quality, speed",
        description="Track the personal face model through a clip, code its parameters, decode "
        "and render them, and score the rendering (unquantised and quantised) against the true "
        "frames beside the frozen first frame and H.264 at the ladder's lowest rung. Without "
        "--video: the built-in talking head (with ground truth), akiyo and carphone (with the "
        "clicked points shipped in codecs/face/).",
    )
    parser.add_argument("--video", metavar="FILE", help="a clip any PyAV reads (needs --face)")
    parser.add_argument(
        "--face", metavar="DESCRIPTION.face", help="its content description (uma describe)"
    )
    parser.add_argument(
        "--frames", type=int, default=150, help="frames per clip from the first (default 150)"
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    import sys
    from pathlib import Path

    from uma.bench.mbc import default_clips, file_clip, format_table, run_mbc_bench
    from uma.cli.cmd_bench import emit
    from uma.errors import ConfigError

    if args.frames < 2:
        raise ConfigError(f"--frames: expected at least 2, got {args.frames}")
    if bool(args.video) != bool(args.face):
        raise ConfigError("--video and --face: expected both (a clip and its description)")
    if args.video:
        from uma.face import load_description
        from uma.mbc.checks import check_description

        video = Path(args.video)
        description = load_description(args.face)
        check_description(description, where=args.face)
        clips = [file_clip(video, description, args.frames)]
    else:
        clips = default_clips(args.frames, seed=args.seed)
    quiet = args.quiet or args.json or not sys.stderr.isatty()

    def progress(name: str) -> None:
        if not quiet:
            print(f"uma bench mbc: {name}...", file=sys.stderr)

    result = run_mbc_bench(clips, seed=args.seed, progress=progress)
    emit(result, format_table(result), as_json=args.json)
    return 0
