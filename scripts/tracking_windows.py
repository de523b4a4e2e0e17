"""Count the face tracker's re-initialisations in every 150-frame window of each clip.

`python scripts/tracking_windows.py` tracks (no coding, no rendering) the built-in talking head
(300 frames), akiyo (300), carphone (382, both from the shipped points files and the shared data
folder) and foreman (raw QCIF, 48 frames, described from codecs/face/foreman.yaml, or
`--foreman DESCRIPTION.face`), and prints per clip:
re-initialisations and failures in frames 0-149 (what the README quotes) and 150-299 (tuning
data), the worst sliding 150-frame window, the tracking step's median wall and CPU ms and cost
evaluations, and each re-initialisation or failure with its reason. A held frame (a failure the
tracker gave without re-initialising) is counted apart. `--json` prints one JSON object instead.
Run from the repository root with the checkout on `PYTHONPATH`. Frame 0's initialisation is not
a re-initialisation.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

WINDOW = 150
FOREMAN = Path("faces/video/foreman_part_qcif.yuv")


def clips(args) -> list[tuple[str, list[np.ndarray], object]]:
    """(name, luma frames, description) of every clip asked for."""
    from uma.bench.mbc import file_clip, talking_head_clip
    from uma.face.clip import describe_clip, load_points
    from uma.paths import codecs_dir

    out = []
    wanted = set(args.only or ["talking-head", "akiyo", "carphone", "foreman"])
    if "talking-head" in wanted:
        clip = talking_head_clip(args.head_frames, seed=args.seed)
        out.append((clip.name, [f[: f.shape[0] * 2 // 3] for f in clip.frames], clip.description))
    for name in ("akiyo", "carphone"):
        if name not in wanted:
            continue
        points = load_points(codecs_dir() / "face" / f"{name}.yaml")
        video = Path(points.video) if points.video is not None else None
        if video is None or not video.is_file():
            print(f"tracking_windows: {name}: no clip at {video}: skipped", file=sys.stderr)
            continue
        clip = file_clip(video, describe_clip(points), 10_000, name=name)
        out.append((name, [f[: f.shape[0] * 2 // 3] for f in clip.frames], clip.description))
    if "foreman" in wanted:
        from uma.paths import shared_data_dir

        path = shared_data_dir() / FOREMAN
        if path.is_file():
            out.append(("foreman", *foreman(path, args.foreman)))
        else:
            print(f"tracking_windows: foreman: no clip at {path}: skipped", file=sys.stderr)
    return out


def foreman(path: Path, description_file: str | None):
    """Foreman's luma frames and description: `description_file`, or one described from the
    points shipped in codecs/face/foreman.yaml on its first frame (the detector finds no face
    there, so `uma describe` refuses it; `describe` itself needs none)."""
    import cv2

    from uma.face import load_description
    from uma.face.describe import describe
    from uma.face.points import read_points
    from uma.paths import codecs_dir
    from uma.video.sources import RawYuvSource

    frames = list(RawYuvSource(path, 176, 144, 25.0).frames())
    if description_file:
        return [f[:144] for f in frames], load_description(description_file)
    points = read_points(codecs_dir() / "face" / "foreman.yaml")
    description = describe(cv2.cvtColor(frames[0], cv2.COLOR_YUV2BGR_I420), points)
    if not description:
        raise SystemExit(f"tracking_windows: foreman: {description.reason}")
    return [f[:144] for f in frames], description


def run(name: str, lumas: list[np.ndarray], description, seed: int, config) -> dict:
    from uma.mbc.encoder import FaceTracker

    FaceTracker(description, rng=seed).track(lumas[0])  # numba loads its kernels
    tracker = FaceTracker(description, config=config, rng=seed)
    events, wall, cpu, evaluations = [], [], [], []
    reinit = np.zeros(len(lumas), bool)
    failed = np.zeros(len(lumas), bool)
    for index, luma in enumerate(lumas):
        begin, begin_cpu = time.perf_counter(), time.process_time()
        result = tracker.track(luma, frame=index)
        spent, spent_cpu = time.perf_counter() - begin, time.process_time() - begin_cpu
        failed[index] = not result
        reinit[index] = bool(result.reinitialised) and index > 0
        if result and not result.reinitialised:
            wall.append(spent * 1000.0)
            cpu.append(spent_cpu * 1000.0)
            evaluations.append(result.evaluations)
        if index > 0 and (reinit[index] or failed[index]):
            kind = "reinit" if reinit[index] else "held"
            events.append(
                f"{index}: {kind}{' (failure)' if failed[index] else ''}: {result.reason}"
            )
    counts = np.convolve(reinit.astype(int), np.ones(WINDOW, int), mode="valid")
    return {
        "frames": len(lumas),
        "reinits": int(reinit.sum()),
        "failures": int(failed.sum()),
        "reinits_0_149": int(reinit[:WINDOW].sum()),
        "reinits_150_299": int(reinit[WINDOW : 2 * WINDOW].sum()) if len(lumas) > WINDOW else None,
        "worst_window_reinits": int(counts.max()) if counts.size else int(reinit.sum()),
        "track_ms_median": round(float(np.median(wall)), 2) if wall else None,
        "track_cpu_ms_median": round(float(np.median(cpu)), 2) if cpu else None,
        "track_cpu_ms_mean": round(float(np.mean(cpu)), 2) if cpu else None,
        "evaluations_median": float(np.median(evaluations)) if evaluations else None,
        "evaluations_mean": round(float(np.mean(evaluations)), 2) if evaluations else None,
        "events": events,
    }


def tracker_config(settings: list[str]):
    """`TrackerConfig` with the `KEY=VALUE` settings applied."""
    import ast

    from uma.mbc.encoder import TrackerConfig

    fields = {}
    for item in settings:
        key, _, value = item.partition("=")
        fields[key] = ast.literal_eval(value)
    return TrackerConfig(**fields)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--only", action="append", help="a clip name (repeatable)")
    parser.add_argument("--foreman", metavar="DESCRIPTION.face", help="foreman's description")
    parser.add_argument("--head-frames", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", action="store_true")
    parser.add_argument(
        "--set", action="append", default=[], metavar="KEY=VALUE",
        help="a TrackerConfig field (a Python literal), e.g. doubt_below=0.5 (repeatable)",
    )  # fmt: skip
    args = parser.parse_args()
    config = tracker_config(args.set)
    out = {name: run(name, lumas, d, args.seed, config) for name, lumas, d in clips(args)}
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    for name, c in out.items():
        print(
            f"{name}: {c['frames']} frames, reinits {c['reinits']} (0-149: {c['reinits_0_149']}, "
            f"150-299: {c['reinits_150_299']}, worst window {c['worst_window_reinits']}), "
            f"failures {c['failures']}, track {c['track_ms_median']} ms "
            f"(CPU {c['track_cpu_ms_median']}), evaluations {c['evaluations_median']} "
            f"(mean {c['evaluations_mean']})"
        )
        for event in c["events"]:
            print(f"    {event}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
