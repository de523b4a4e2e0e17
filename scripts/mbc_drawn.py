"""The face box's error outside the face split by what the receiver draws there, and a bound.

    PYTHONPATH=$PWD python scripts/mbc_drawn.py [--start 0] [--frames 150] [--clips akiyo,carphone]

Runs `scripts/mbc_anatomy.py`'s steps (the bench's tracking, mirror, stream and receiver) and,
per pixel of the face box outside the face mesh at the tracked pose, notes what the receiver
drew there: the plate where it was seen, the plate where it was filled (never seen), the torso,
or the head's halo and head ring. Prints each one's share of the box and MSE for the MBC alone,
the frozen display and H.264 16k. Then a bound no receiver reaches: per pixel, the least error
of the MBC's picture, the frozen one and the reference moved rigidly with the head, outside the
face and over the whole box (docs/mbc.md, session mbc6). The drawn layers are read by wrapping
`uma.mbc.layered_render`'s own steps for the run.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import sys
from pathlib import Path

import numpy as np

KINDS = ("plate seen", "plate filled", "torso", "halo and head ring")
SHOWN = ("mbc", "frozen", "h264")


def _recorder() -> dict:
    """Wrap the layered renderer's steps so each rendering leaves its person and torso masks
    (the torso's as `_torso_layer` gives it: drawn, or kept from the last call)."""
    import uma.mbc.layered_render as layered

    drawn: dict = {}
    soften, torso_layer = layered.soften_outline, layered._torso_layer

    def recording_soften(out, person, face, moved, *more):
        drawn["person"] = person.copy()
        return soften(out, person, face, moved, *more)

    def recording_torso(*args):
        layer = torso_layer(*args)
        drawn["torso"] = layer[2].copy()
        return layer

    layered.soften_outline, layered._torso_layer = recording_soften, recording_torso
    return drawn


def run(clip) -> dict:
    """Sums of squared luma error per kind and display, and the bound's, over the clip."""
    import cv2

    sys.path.insert(0, str(Path(__file__).parent))
    from mbc_anatomy import coded_run, region_labels

    from uma.bench.mbc_scores import face_box
    from uma.mbc.layers import head_ring_points, rigid_fit

    drawn = _recorder()
    lumas, results, units, receiver, decoded, h264 = coded_run(clip)
    height, width = lumas[0].shape
    sums = {"box_px": 0, "px": np.zeros(len(KINDS)), "sse": np.zeros((len(KINDS), len(SHOWN))),
            "bound_outside": np.zeros(3), "bound_box": np.zeros(3)}  # fmt: skip
    box, params, shown, kinds, moved = None, results[0].params, None, None, lumas[0]
    for index in range(len(lumas)):
        if results[index]:
            params = results[index].params
        if index in decoded:
            drawn.clear()
            p, light = units.split(decoded[index])
            shown, _ = receiver.render(p, light, units.body_of(decoded[index]))
            torso = drawn["torso"] > 0
            person, known = drawn["person"], receiver.plate.known
            kinds = np.select([person, torso, known], [3, 2, 0], 1)
            target = head_ring_points(receiver.scene, receiver.scene.points(p))
            matrix = rigid_fit(receiver._reference_ring, target)
            moved = cv2.warpAffine(lumas[0], matrix, (width, height), flags=cv2.INTER_LINEAR,
                                   borderMode=cv2.BORDER_REPLICATE)  # fmt: skip
        box = face_box(lumas[index], None, box)
        if index == 0 or box is None or shown is None:
            continue
        labels = region_labels(receiver, params, box)
        inside, outside = labels >= 0, labels >= 2
        truth = lumas[index].astype(np.float64)
        errors = [(truth - picture[:height]) ** 2 for picture in (shown, lumas[0], h264[index])]
        best = np.minimum(np.minimum(errors[0], errors[1]), (truth - moved) ** 2)
        sums["box_px"] += int(inside.sum())
        for k in range(len(KINDS)):
            where = outside & (kinds == k)
            sums["px"][k] += where.sum()
            sums["sse"][k] += [float(e[where].sum()) for e in errors]
        for key, where in (("bound_outside", outside), ("bound_box", inside)):
            sums[key] += [float(best[where].sum()), float(errors[0][where].sum()),
                          float(errors[2][where].sum())]  # fmt: skip
        sums.setdefault("outside_px", 0)
        sums["outside_px"] += int(outside.sum())
    return sums


def report(name: str, sums: dict) -> None:
    box_px = max(sums["box_px"], 1)
    print(f"\n{name}: what the receiver draws outside the face (share of the box, MSE "
          f"{' / '.join(SHOWN)}, part of the box's MSE {SHOWN[0]} / {SHOWN[2]})")  # fmt: skip
    for k, kind in enumerate(KINDS):
        px = max(sums["px"][k], 1)
        mse = sums["sse"][k] / px
        part = sums["sse"][k] / box_px
        print(f"  {kind:20s} {sums['px'][k] / box_px:5.3f} | "
              + " / ".join(f"{v:6.0f}" for v in mse) + f" | {part[0]:5.0f} / {part[2]:5.0f}")  # fmt: skip
    for key, px in (("bound_outside", sums.get("outside_px", 1)), ("bound_box", box_px)):
        best, ours, h264 = sums[key] / max(px, 1)
        print(f"  {key}: MSE best of (MBC, frozen, moved reference) {best:.0f}, MBC {ours:.0f}, "
              f"H.264 {h264:.0f}")  # fmt: skip


def main() -> None:
    from uma.bench.mbc_clips import default_clips

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--start", type=int, default=0)
    parser.add_argument("--frames", type=int, default=150)
    parser.add_argument("--clips", default="akiyo,carphone")
    args = parser.parse_args()
    for clip in default_clips(args.frames, start=args.start):
        if clip.name in args.clips.split(","):
            report(clip.name, run(clip))


if __name__ == "__main__":
    main()
