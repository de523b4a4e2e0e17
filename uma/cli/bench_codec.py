"""`uma bench codec`: each codec's rate and quality per ladder rung, codec speed, metric costs."""

from __future__ import annotations

import argparse

__all__ = ["register"]

CLIPS = ("akiyo.mp4", "carphone_qcif.mp4")


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "codec",
        help="rate and quality per ladder rung of H.264, VP8, AV1; encode/decode speed; "
        "SSIM and PSNR cost",
        description="Code clips (akiyo and carphone from ../shared/data/faces/video, or --video) "
        "at every rung of each codec's ladder (codecs/<codec>.yaml) and print per rung the target "
        "and measured rate (after the first second), PSNR and SSIM over the whole frame and the "
        "face box, and encode and decode ms per frame. With H.264 also libx264's rate accuracy "
        "on one clip, its speed, and the cost of SSIM and PSNR on one luma plane.",
    )
    from uma.codecs import full_frame_names

    parser.add_argument(
        "--codec",
        choices=(*full_frame_names(), "all"),
        default="h264",
        help="codec to measure (default h264; all: every one)",
    )
    parser.add_argument(
        "--video",
        metavar="FILE",
        help="one clip instead of akiyo and carphone (default ../shared/data/faces/video/)",
    )
    parser.add_argument("--frames", type=int, default=300, help="frames per clip (default 300)")
    parser.add_argument("--plot", metavar="PNG", help="draw the rate-quality curves into PNG")
    parser.add_argument(
        "--ffmpeg",
        action="store_true",
        help="code every rung again with the ffmpeg command line at the same settings and "
        "compare the rates",
    )
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    import sys
    from pathlib import Path

    from uma.bench.codec import (
        CODEC_NAMES,
        format_codecs_table,
        format_table,
        plot_rate_quality,
        run_codec_bench,
        run_codecs_bench,
    )
    from uma.bench.codec_clip import MIN_FRAMES
    from uma.cli.cmd_bench import emit
    from uma.errors import ConfigError
    from uma.paths import check_regular_file, shared_data_dir

    if args.frames < MIN_FRAMES:
        raise ConfigError(f"--frames: expected at least {MIN_FRAMES}, got {args.frames}")
    if args.video is not None:
        try:
            check_regular_file(args.video, error=ConfigError, what="video file")
        except ConfigError as err:
            raise ConfigError(f"--video: {err}") from None
    if args.plot and not Path(args.plot).parent.is_dir():
        raise ConfigError(f"--plot: expected a file in an existing folder, got {args.plot!r}")
    folder = shared_data_dir() / "faces" / "video"
    if args.video:
        videos = [Path(args.video)]
    else:
        videos = [folder / name for name in CLIPS if (folder / name).is_file()] or [None]
    codecs = CODEC_NAMES if args.codec == "all" else (args.codec,)
    _note_the_work(videos, args.frames, codecs, quiet=args.quiet)

    def progress(what: str) -> None:
        if not args.quiet and sys.stderr.isatty():
            print(f"\r  {what:<40}", end="", file=sys.stderr, flush=True)

    result, tables = {}, []
    if "h264" in codecs:
        legacy_video = Path(args.video) if args.video else folder / "akiyo.mp4"
        legacy_video = legacy_video if legacy_video.is_file() else None  # the pattern
        result = run_codec_bench(video=legacy_video, frames=args.frames)
        tables.append(format_table(result))
    result.update(run_codecs_bench(codecs, videos, frames=args.frames, progress=progress))
    tables.append(format_codecs_table(result))
    if args.ffmpeg:
        from uma.bench.codec_ffmpeg import compare_codecs, format_ffmpeg_table

        result["ffmpeg"] = compare_codecs(codecs, videos, frames=args.frames, progress=progress)
        tables.append(format_ffmpeg_table(result["ffmpeg"]))
    if not args.quiet and sys.stderr.isatty():
        print("\r" + " " * 44 + "\r", end="", file=sys.stderr)
    if args.plot:
        plot_rate_quality(result, Path(args.plot))
        tables.append(f"rate-quality plot: {args.plot}")
    emit(result, "\n\n".join(tables), as_json=args.json)
    return 0


def _note_the_work(videos: list, frames: int, codecs: tuple[str, ...], *, quiet: bool) -> None:
    """Refuse a clip the benchmark cannot score, and say on stderr what a large one will cost
    (in pixels coded and scored, against the default clips') before spending it."""
    import sys

    from uma.bench.codec_clip import work_pixels
    from uma.video import default_ladder_path, load_ladder

    rungs = sum(len(load_ladder(default_ladder_path(codec)).rungs) for codec in codecs)
    total, largest = work_pixels(videos, frames, rungs)
    usual = (352 * 288 + 176 * 144) * 300 * rungs  # akiyo (CIF) and carphone (QCIF), 300 frames
    if total > 10 * usual and not quiet:
        print(
            f"uma bench codec: {largest} at {rungs} rungs: {total:.2g} pixels to code and score, "
            f"{total / usual:.0f} times the default clips' {usual:.2g}; --frames bounds it",
            file=sys.stderr,
        )
