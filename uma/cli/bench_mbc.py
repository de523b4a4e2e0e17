"""`uma bench mbc`: the model-based codec on the talking head, akiyo and carphone, or a clip."""

from __future__ import annotations

import argparse

from uma.cli.args import frame_size

__all__ = ["register"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "mbc",
        help="model-based codec: track, code, decode and render a clip; rates, quality, speed",
        description="Track the personal face model through a clip, code its parameters and the "
        "face's light, decode them and render the whole scene from the first frame, and score "
        "the rendering (unquantised and quantised) in the face box, the whole frame and the "
        "model's pixels against the true frames, beside the frozen first frame and H.264 at the "
        "ladder's lowest and second rungs. Without "
        "--video: the built-in talking head (with ground truth), akiyo and carphone (with the "
        "clicked points shipped in codecs/face/).",
    )
    parser.add_argument(
        "--video",
        metavar="FILE",
        help="a clip any PyAV reads, or raw YUV 4:2:0 (.yuv, with --size) (needs --face)",
    )
    parser.add_argument(
        "--size", type=frame_size, metavar="WxH", help="a .yuv clip's frame size, e.g. 176x144"
    )
    parser.add_argument(
        "--fps", type=float, default=25.0, help="a .yuv clip's frame rate (default 25)"
    )
    parser.add_argument(
        "--face", metavar="DESCRIPTION.face", help="its content description (uma describe)"
    )
    parser.add_argument(
        "--frames", type=int, default=150, help="frames per clip from the first (default 150)"
    )
    parser.add_argument(
        "--picture",
        metavar="FILE.png",
        help="also draw source | MBC | H.264 alone at one instant of each clip into FILE.png",
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    import sys
    from pathlib import Path

    from uma.bench.mbc import default_clips, file_clip, format_table, run_model_bench
    from uma.bench.mbc_clips import check_clip, check_first_frame
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
        if video.suffix.lower() == ".yuv":
            from uma.bench.mbc_clips import yuv_clip

            if args.size is None:
                raise ConfigError(f"{video}: a raw YUV clip: expected --size WxH (e.g. 176x144)")
            clips = [yuv_clip(video, args.size, args.fps, description, args.frames)]
        else:
            clips = [file_clip(video, description, args.frames)]
        check_clip(clips[0], args.face)
        check_first_frame(clips[0])
    else:
        clips = default_clips(args.frames, seed=args.seed)
    quiet = args.quiet or args.json or not sys.stderr.isatty()

    def progress(name: str) -> None:
        if not quiet:
            print(f"uma bench mbc: {name}...", file=sys.stderr)

    picture = Path(args.picture) if args.picture else None
    if picture is not None and not picture.parent.is_dir():
        raise ConfigError(f"--picture: expected a file in an existing folder, got {picture}")
    result = run_model_bench(clips, seed=args.seed, progress=progress, picture=picture)
    emit(result, format_table(result), as_json=args.json)
    return 0
