"""`uma source synth --out clip.mp4`: write a talking-head clip and its ground truth."""

from __future__ import annotations

import argparse

from uma.cli.args import frame_size

__all__ = ["register"]

HELP = """\
Write a synthetic talking-head clip: the astronaut photograph animated by the face model
(head turns, nods, speech-like jaw and lips, blinks, changing light, sensor noise), encoded
with libx264 at high quality (CRF 16), and beside it CLIP.truth.json with every frame's model
parameters (tx_px, ty_px, scale_px, rx_rad, ry_rad, rz_rad, action units), projected model
points (pixels) and light (gain; unit direction in camera coordinates, x right, y up, z toward
the camera). Scenarios use the same source with `source: {kind: talking-head}`.

With --fap FILE an MPEG-4 FBA .fap file drives the head instead: frame i of the clip is frame i
of the file, at the file's frame rate; head rotation from FAPs 48-50 (pitch, yaw, roll) and the
action units from the low-level FAPs (jaw, lips, eyelids, brows), added to the photograph's own
pose and expression; position, scale and light are held still (sensor noise stays). --frames
defaults to the file's length."""


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "source",
        help="synthetic sources with ground truth",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    kinds = parser.add_subparsers(dest="kind", metavar="KIND")
    synth = kinds.add_parser(
        "synth",
        help="talking-head clip plus ground truth",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    synth.add_argument("--out", required=True, metavar="CLIP.mp4", help="clip to write")
    synth.add_argument(
        "--frames", type=int, help="frames (default 250, 10 s; with --fap the file's)"
    )
    synth.add_argument("--size", type=frame_size, default=(352, 288), help="WxH (default 352x288)")
    synth.add_argument(
        "--fps", type=float, help="frame rate (default 25; with --fap the file's, and only it)"
    )
    synth.add_argument(
        "--fap", metavar="FILE", help="animate from an MPEG-4 FBA .fap file (see above)"
    )
    synth.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    synth.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    synth.set_defaults(func=handle_synth)
    parser.set_defaults(func=lambda args: (parser.print_help(), 2)[1])


def handle_synth(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.atomic import prepare_out_dir
    from uma.errors import OutputError, UmaError

    out = Path(args.out)
    if out.is_dir():
        raise OutputError(f"--out: expected a clip file name, got the folder {str(out)!r}")
    prepare_out_dir(out.parent, what="--out")
    try:
        return _synth(args)
    except UmaError:
        raise
    except OSError as err:
        where = err.filename or args.out
        raise OutputError(f"{where}: cannot write ({err.strerror or err})") from None


def _synth(args: argparse.Namespace) -> int:
    import json
    from pathlib import Path

    from uma.atomic import atomic_write_text
    from uma.face import TalkingHeadSource, read_fap

    sequence = read_fap(args.fap) if args.fap else None
    _settle_frames_and_fps(args, sequence)
    out = Path(args.out)
    width, height = args.size
    source = TalkingHeadSource(
        width, height, args.fps, seed=args.seed, frame_count=args.frames, fap=sequence
    )
    truth = _write_clip(args, source, out)
    document = {
        "clip": out.name,
        "size": [width, height],
        "fps": args.fps,
        "seed": args.seed,
        "fap": str(Path(args.fap).resolve()) if args.fap else None,
        "param_names": [
            "tx_px",
            "ty_px",
            "scale_px",
            "rx_rad",
            "ry_rad",
            "rz_rad",
            *source.model.action_unit_names,
        ],
        "triangles": source.model.triangles.tolist(),
        "frames": truth,
    }
    truth_path = out.with_suffix(".truth.json")
    atomic_write_text(truth_path, json.dumps(document) + "\n")
    print(
        f"{out}: {args.frames} frames {width}x{height}@{args.fps:g}; ground truth in {truth_path}"
    )
    return 0


def _settle_frames_and_fps(args: argparse.Namespace, sequence) -> None:
    """`args.frames` and `args.fps` from the command line, the `.fap` `sequence` (None: none)
    and the defaults; a `ConfigError` for what does not fit."""
    from uma.errors import ConfigError
    from uma.face.fap import MAX_FPS, MIN_FPS

    if sequence is not None:
        if args.fps is not None and args.fps != sequence.fps:
            raise ConfigError(
                f"--fps {args.fps:g}: {args.fap} plays at {sequence.fps:g} frames/s; "
                "leave --fps out with --fap"
            )
        if len(sequence) == 0:
            raise ConfigError(f"{args.fap}: the file holds no frame")
        if args.frames is not None and args.frames > len(sequence):
            raise ConfigError(
                f"--frames {args.frames}: {args.fap} holds only {len(sequence)} frames"
            )
        args.fps = sequence.fps
        args.frames = args.frames if args.frames is not None else len(sequence)
    args.frames = 250 if args.frames is None else args.frames
    args.fps = 25.0 if args.fps is None else args.fps
    if args.frames <= 0 or args.seed < 0:
        raise ConfigError("--frames and --seed: expected positive numbers (seed >= 0)")
    if not MIN_FPS <= args.fps <= MAX_FPS:  # also refuses NaN
        raise ConfigError(f"--fps: expected {MIN_FPS:g}-{MAX_FPS:g} frames/s, got {args.fps:g}")


def _write_clip(args: argparse.Namespace, source, out) -> list[dict]:
    """The talking head's frames encoded into `out` (H.264 in MP4, written atomically); each
    frame's ground truth."""
    import sys
    from fractions import Fraction

    import av

    from uma.atomic import atomic_open

    truth = []
    rate = Fraction(args.fps).limit_denominator(1001)
    with atomic_open(out, "wb") as handle:
        container = av.open(handle, "w", format="mp4")
        stream = container.add_stream("libx264", rate=rate)
        stream.width, stream.height, stream.pix_fmt = source.width, source.height, "yuv420p"
        stream.options = {"crf": "16", "preset": "medium"}
        frames = source.frames()
        if not args.quiet and sys.stderr.isatty():
            from tqdm import tqdm

            frames = tqdm(frames, total=args.frames, unit="frame", file=sys.stderr, leave=False)
        for index, frame in enumerate(frames):
            picture = av.VideoFrame.from_ndarray(frame, format="yuv420p")
            picture.pts = index
            container.mux(stream.encode(picture))
            truth.append(_truth_row(index, source.ground_truth(index)))
        container.mux(stream.encode(None))
        container.close()
    return truth


def _truth_row(index: int, gt: dict) -> dict:
    """One frame's ground truth as the truth file holds it (rounded)."""
    return {
        "frame": index,
        "params": [round(float(v), 6) for v in gt["params"]],
        "points_px": [[round(float(x), 3), round(float(y), 3)] for x, y in gt["points"]],
        "light_gain": round(gt["light_gain"], 6),
        "light_direction": [round(float(v), 6) for v in gt["light_direction"]],
    }
