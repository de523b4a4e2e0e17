"""The model path's stages with OpenCV on one thread and on its default pool, alternated in one
process.

    .venv/bin/python scripts/mbc_threads.py [--reps N] [--frames N] [--threads K]

`import uma` runs OpenCV on one thread (`uma.blas.pin_opencv_threads`); this switches between
that and `--threads` (default: the cores, OpenCV's own default) with `cv2.setNumThreads` before
each `uma.bench.mbc.run_clip` (the talking head and akiyo, the lowest refresh only), the order
alternated each repetition, and prints one JSON line a run (load, `stages_ms`,
`stages_cpu_ms`, the model path's wall and CPU sums), then the medians per clip and count.
The scores are not compared here: `uma bench mbc --json` with `OPENCV_FOR_THREADS_NUM` set
each way compares them.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import json
import os
import statistics


def main() -> None:
    import cv2

    from uma.bench.mbc import run_clip
    from uma.bench.mbc_clips import default_clips
    from uma.bench.mbc_refresh import DEFAULT_REFRESH

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reps", type=int, default=3, help="repetitions of each (default 3)")
    parser.add_argument("--frames", type=int, default=150, help="frames a clip (default 150)")
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 2, help="the pool")
    args = parser.parse_args()
    clips = [c for c in default_clips(args.frames) if c.name in ("talking-head", "akiyo")]
    refresh = {"mbc_refresh_lowest": DEFAULT_REFRESH["mbc_refresh_lowest"]}
    for clip in clips:  # numba's kernels and the caches warm
        run_clip(clip, refresh=refresh)
    runs = []
    for rep in range(args.reps):
        for threads in (1, args.threads) if rep % 2 == 0 else (args.threads, 1):
            cv2.setNumThreads(threads)
            for clip in clips:
                out = run_clip(clip, refresh=refresh)
                runs.append({"clip": clip.name, "threads": threads,
                             "load_1m": round(os.getloadavg()[0], 2),
                             "stages_ms": out["stages_ms"], "stages_cpu_ms": out["stages_cpu_ms"],
                             "model_path_ms": out["model_path_ms"],
                             "model_path_cpu_ms": out["model_path_cpu_ms"]})  # fmt: skip
                print(json.dumps(runs[-1]), flush=True)
    medians = {}
    for run in runs:
        medians.setdefault(f"{run['clip']} threads={run['threads']}", []).append(run)
    for key, group in medians.items():
        summary = {
            kind: {
                stage: round(statistics.median(r[kind][stage] for r in group), 3)
                for stage in group[0][kind]
            }
            for kind in ("stages_ms", "stages_cpu_ms")
        }
        for total in ("model_path_ms", "model_path_cpu_ms"):
            summary[total] = round(statistics.median(r[total] for r in group), 3)
        print(json.dumps({"medians": key, **summary}))


if __name__ == "__main__":
    main()
