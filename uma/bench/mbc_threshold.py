"""How the tracker's lost-track threshold was measured: scores of good and of lost tracks.

Units: scores are correlations (`uma.mbc.encoder`); distances in pixels.

Run `python -m uma.bench.mbc_threshold` (a one-off measurement, not a benchmark). On data the
README's `uma bench mbc` figures do not use (the talking head at seed 1; akiyo and carphone
from frame 150 on), it tracks with the threshold off and records every frame's score (good
tracks: on the talking head only those within 1.5 px of the ground truth). Then, from each
tracked frame's parameters moved by a lost track's typical error (a shift of 0.15 to 0.3 face
widths, or a turn of 0.3 rad, with the prediction carried on), it runs the same tracking step
and records the score of every result that settles more than 3 px (RMS over the vertices) from
the good track: lost tracks. It prints both distributions per clip.
"""

from __future__ import annotations

import numpy as np

__all__ = ["measure"]


def _clip_frames(name: str, start: int, count: int) -> list[np.ndarray]:
    from uma.paths import shared_data_dir
    from uma.video import VideoFileSource

    files = {"akiyo": "akiyo.mp4", "carphone": "carphone_qcif.mp4"}
    source = VideoFileSource(shared_data_dir() / "faces" / "video" / files[name])
    frames = []
    for index, frame in enumerate(source.frames()):
        if index >= start + count:
            break
        if index >= start:
            frames.append(frame[: frame.shape[0] * 2 // 3])
    return frames


def measure(name: str, frames: list[np.ndarray], description, truth=None, *, rng=0) -> dict:
    from uma.face.geometry import project
    from uma.fit.mde import mde_px
    from uma.mbc.encoder import FaceTracker, TrackerConfig

    rng = np.random.default_rng(rng)
    # The threshold off for the good tracks; on (the default) for the lost ones, so that a
    # step that scores low goes on as the tracker's would before it is given up.
    tracker = FaceTracker(description, config=TrackerConfig(lost_below=-1.0), rng=0)
    stepper = FaceTracker(description, rng=0)
    model = description.model
    good, lost = [], []
    for index, picture in enumerate(frames):
        result = tracker.track(picture)
        if not result:
            continue
        if truth is not None and mde_px(model, result.params, truth(index)) > 1.5:
            continue
        good.append(result.score)
        if index % 3:
            continue
        image = np.asarray(picture, dtype=np.float32)
        width = float(np.ptp(project(model, result.params)[:, 0]))
        for _ in range(2):
            start = result.params.copy()
            angle = rng.uniform(0, 2 * np.pi)
            shift = rng.uniform(0.15, 0.3) * width
            start[0] += shift * np.cos(angle)
            start[1] += shift * np.sin(angle)
            if rng.random() < 0.3:
                start[4] += rng.choice([-0.3, 0.3])
            params, score, _ = stepper.step(image, start)
            if mde_px(model, params, result.params) > 3.0:
                lost.append(score)
    good_a, lost_a = np.array(good), np.array(lost)

    def summary(values):
        if values.size == 0:
            return {}
        return {
            "n": int(values.size),
            **{
                f"p{q}": round(float(np.percentile(values, q)), 3)
                for q in (0, 1, 5, 50, 95, 99, 100)
            },
        }

    return {"clip": name, "good": summary(good_a), "lost": summary(lost_a)}


def main() -> None:
    import json

    import cv2

    from uma.face.clip import describe_clip
    from uma.face.talking_head import TalkingHeadSource
    from uma.paths import codecs_dir

    head = TalkingHeadSource(352, 288, seed=1)
    noise = np.random.default_rng(1)
    frames = [cv2.cvtColor(head.render_bgr(i, rng=noise), cv2.COLOR_BGR2GRAY) for i in range(150)]
    print(json.dumps(measure("talking-head seed 1", frames, head.description, head.params_at)))
    for name in ("akiyo", "carphone"):
        description = describe_clip(codecs_dir() / "face" / f"{name}.yaml")
        frames = _clip_frames(name, 150, 150)
        print(json.dumps(measure(f"{name} frames 150-299", frames, description)))


if __name__ == "__main__":
    main()
