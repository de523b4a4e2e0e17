"""Share of H.264 bits spent on key frames along a run's rung schedule: reopen vs set_target.

`python scripts/keyframe_free.py RESULTS_DIR` reads `frames.csv` and `events.csv` of a
`uma run` (the default scenario: `python -m uma run --out RESULTS_DIR`), takes from them which
captured frame the engine coded with H.264 at which ladder rung and where the receiver asked for
a key frame, and codes the same frames of a clip twice with libx264:
- `reopen`: what the simulation's codec chain does today, a new encoder (an IDR) on every
  change of rung and on the return from the model codec;
- `set_target`: an encoder per picture size, opened as `Ladder.open_span` says, that follows
  rate and frame-rate changes at its size with `H264Encoder.set_target` (no IDR); a size change
  or the return from the model codec opens a new one. Its VBV buffer is `vbv_frames` frame
  intervals of the rung it opens at;
- `set_target-top`: the same with the buffer sized at the top rate of the size;
- `set_target-mid`: at the geometric mean of the size's lowest and highest rate.
Both force an IDR where the run had a key-frame request (`--no-requests` leaves them out).
Clips: the built-in talking head (CIF, as the default scenario sends) and akiyo (CIF, played
forwards then backwards so the loop has no cut), `--clip` to choose. Per clip and path it
prints H.264 kbit, key-frame kbit and share, key frames by cause (opening, request, periodic
`keyint_frames`) and, for the changes of rung at the same size (down and up), the kbit in the
second after the change over the new rung's rate: [count, median, min, max]; the backlog a
link draining at the current rung's rate would hold after each frame, in ms (p95, max); and the
mean luma PSNR of the decoded frames against the pictures coded (at the rung's size). `--json` prints one JSON object. Run from the repository root with the checkout
on `PYTHONPATH`.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import csv
import json
import sys
from pathlib import Path

import numpy as np

FPS = 25.0


def schedule(results: Path) -> tuple[list[tuple[int, int]], set[int]]:
    """[(captured frame, H.264 point, first after the model codec)] the run coded with H.264,
    and the frames that follow a key-frame request (the first coded frame at or after each)."""
    coded, previous = [], None
    with open(results / "frames.csv", newline="") as handle:
        for row in csv.DictReader(handle):
            if row["scheduled"] != "1":
                continue
            if row["codec"] == "h264":
                coded.append((int(row["frame"]), int(row["rung"]), previous == "mbc"))
            previous = row["codec"]
    requests = []
    with open(results / "events.csv", newline="") as handle:
        for row in csv.DictReader(handle):
            if row["kind"] == "keyframe_request":
                requests.append(float(row["time_ms"]) / 1000.0 * FPS)
    forced = set()
    frames = np.array([c[0] for c in coded])
    for at in requests:
        later = frames[frames >= at]
        if len(later):
            forced.add(int(later[0]))
    return coded, forced


def clip_frames(name: str, count: int) -> list[np.ndarray]:
    """`count` CIF YUV 4:2:0 frames of the clip (akiyo played back and forth)."""
    if name == "talking-head":
        from uma.bench.mbc import talking_head_clip

        return talking_head_clip(count).frames
    from uma.paths import shared_data_dir
    from uma.video import VideoFileSource

    source = list(VideoFileSource(shared_data_dir() / "faces" / "video" / "akiyo.mp4").frames())
    loop = source + source[-2:0:-1]
    return [loop[i % len(loop)] for i in range(count)]


PATHS = ("reopen", "set_target", "set_target-mid", "set_target-top")


def open_encoder(rung, ladder, path: str):
    """A new encoder for `rung`: the rung's own (`reopen`), or one for every rung of its size,
    its VBV buffer sized at `rung` (`set_target`), at the top of the size (`-top`) or at the
    geometric mean of the size's lowest and highest rate (`-mid`), at the opening frame rate."""
    from uma.video import H264Encoder

    settings = ladder.encoder.kwargs()
    if path == "reopen":
        return H264Encoder(rung.width, rung.height, rung.fps, rung.rate_kbps, **settings)
    fps, ceiling = ladder.open_span(rung)
    opening = {
        "set_target-top": ceiling,
        "set_target-mid": (
            ceiling * min(r.rate_kbps * fps / r.fps for r in same_size(ladder, rung))
        )
        ** 0.5,
    }.get(path, rung.rate_kbps * fps / rung.fps)
    encoder = H264Encoder(rung.width, rung.height, fps, opening, max_rate_kbps=ceiling, **settings)
    encoder.set_target(rung.rate_kbps, rung.fps)
    return encoder


def same_size(ladder, rung):
    return [r for r in ladder.rungs if (r.width, r.height) == (rung.width, rung.height)]


def code(frames, coded, forced, ladder, path: str) -> dict:
    """Code the schedule along `path` (one of `PATHS`) and summarise it."""
    from uma.metrics.quality import psnr_db
    from uma.video import H264Decoder, resize_yuv420

    encoder, size, last_point = None, None, None
    decoder, rows, scores = H264Decoder(conceal=False), [], []
    for frame, point, returning in coded:
        rung = ladder.rungs[point - 1]
        cause = None
        if point != last_point or returning or encoder is None:
            same_size = size == (rung.width, rung.height) and not returning
            kept = path != "reopen" and same_size
            if not (kept and encoder.set_target(rung.rate_kbps, rung.fps)):
                cause = "opening"
                encoder = open_encoder(rung, ladder, path)
                size = (rung.width, rung.height)
        picture = resize_yuv420(frames[frame], rung.width, rung.height)
        request = frame in forced and cause is None
        out = encoder.encode(picture, force_idr=request)
        decoded = decoder.decode(out.data)
        scores.append(psnr_db(picture[: rung.height], decoded[: rung.height]))
        if out.is_keyframe and cause is None:
            cause = "request" if request else "periodic"
        rows.append((frame, point, out.size_bits, cause))
        last_point = point
    return {**summarise(rows, ladder), "psnr_db_mean": round(float(np.mean(scores)), 2)}


def backlog_ms(rows, ladder) -> list[float]:
    """After each frame, the backlog of a link draining at the current rung's rate, in ms of
    that rate (a leaky bucket; the queue these bits alone would build)."""
    level, last, out = 0.0, None, []
    for frame, point, size, _ in rows:
        rate_bps = 1000.0 * ladder.rungs[point - 1].rate_kbps
        if last is not None:
            level = max(0.0, level - rate_bps * (frame - last) / FPS)
        level += size
        last = frame
        out.append(1000.0 * level / rate_bps)
    return out


def summarise(rows, ladder) -> dict:
    total = sum(r[2] for r in rows)
    key = sum(r[2] for r in rows if r[3])
    causes = {c: sum(1 for r in rows if r[3] == c) for c in ("opening", "request", "periodic")}
    # the second after each change of point at the same size, against the new rung's rate
    ratios: dict[str, list[float]] = {"down": [], "up": []}
    for i in range(1, len(rows)):
        before, after = ladder.rungs[rows[i - 1][1] - 1], ladder.rungs[rows[i][1] - 1]
        if before == after or (before.width, before.height) != (after.width, after.height):
            continue
        start, point = rows[i][0], rows[i][1]
        window = [r for r in rows[i:] if r[0] < start + FPS]
        if all(r[1] == point for r in window) and window[-1][0] >= start + FPS - 3:
            way = "down" if after.rate_kbps < before.rate_kbps else "up"
            ratios[way].append(sum(r[2] for r in window) / 1000.0 / after.rate_kbps)
    queue = backlog_ms(rows, ladder)
    return {
        "h264_kbit": round(total / 1000.0, 1),
        "backlog_ms_p95": round(float(np.percentile(queue, 95)), 1),
        "backlog_ms_max": round(max(queue), 1),
        "keyframe_kbit": round(key / 1000.0, 1),
        "keyframe_bits_share": round(key / total, 4),
        "keyframes": causes,
        "frames": len(rows),
        **{
            f"second_after_{way}_ratio": [
                len(values),
                round(float(np.median(values)), 3),
                round(min(values), 3),
                round(max(values), 3),
            ]
            for way, values in ratios.items()
            if values
        },
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="a `uma run` results folder")
    parser.add_argument("--clip", action="append", choices=["talking-head", "akiyo"])
    parser.add_argument("--no-requests", action="store_true", help="no forced key frames")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    from uma.video import load_ladder

    for name in ("frames.csv", "events.csv"):
        if not (args.results / name).is_file():
            print(
                f"error: {args.results / name}: no such file (a `uma run` folder?)", file=sys.stderr
            )
            return 2
    coded, forced = schedule(args.results)
    if args.no_requests:
        forced = set()
    ladder, out = load_ladder(), {}
    for clip in args.clip or ["talking-head", "akiyo"]:
        frames = clip_frames(clip, max(c[0] for c in coded) + 1)
        out[clip] = {path: code(frames, coded, forced, ladder, path) for path in PATHS}
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    for clip, paths in out.items():
        for path, figures in paths.items():
            print(f"{clip:13} {path:15} " + " ".join(f"{k}={v}" for k, v in figures.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
