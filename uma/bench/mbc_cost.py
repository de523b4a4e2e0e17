"""CPU cost per fitting-cost evaluation of MBC's initialisation and tracking: the defaults of
`engine.mbc.init_us_per_evaluation` and `track_us_per_evaluation`.

Units: microseconds of CPU time (`time.process_time`, so other work on a shared machine does
not inflate it) per evaluation the tracker reports. Run `python -m uma.bench.mbc_cost [--seed N]
[--frames N] [--every N]`: the talking head at CIF, re-initialised every `--every` frames.
"""

from __future__ import annotations

import argparse
import statistics
import time


def measure(*, seed: int = 2, frames: int = 120, every: int = 30) -> dict:
    """Medians of CPU microseconds per evaluation, evaluations and ms, for inits and tracks."""
    import cv2
    import numpy as np

    from uma.face.talking_head import TalkingHeadSource
    from uma.mbc.encoder import FaceTracker

    source = TalkingHeadSource(352, 288, seed=seed)
    noise = np.random.default_rng(seed)
    lumas = [
        cv2.cvtColor(source.render_bgr(i, rng=noise), cv2.COLOR_BGR2YUV_I420)[:288]
        for i in range(frames)
    ]
    FaceTracker(source.description, rng=seed).track(lumas[0])  # numba compiles on first use
    tracker = FaceTracker(source.description, rng=seed)
    rows: dict[str, list[tuple[float, int]]] = {"init": [], "track": []}
    for index, picture in enumerate(lumas):
        if index % every == 0:
            tracker.reset()
        start = time.process_time()
        result = tracker.track(picture, frame=index)
        spent_us = (time.process_time() - start) * 1e6
        rows["init" if result.reinitialised else "track"].append((spent_us, result.evaluations))
    out = {}
    for kind, values in rows.items():
        if values:
            out[kind] = {
                "count": len(values),
                "us_per_evaluation_median": round(
                    statistics.median(us / max(ev, 1) for us, ev in values), 1
                ),
                "evaluations_median": statistics.median(ev for _, ev in values),
                "ms_median": round(statistics.median(us for us, _ in values) / 1000.0, 2),
            }
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=2)
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--every", type=int, default=30)
    args = parser.parse_args()
    for kind, row in measure(seed=args.seed, frames=args.frames, every=args.every).items():
        print(kind, row)


if __name__ == "__main__":
    main()
