"""Where in the face box the model-based codec loses against H.264's lowest rung, and when.

    PYTHONPATH=$PWD python scripts/mbc_anatomy.py [--start 0] [--frames 150]
        [--clips akiyo,carphone] [--worst 3] [--png-dir /tmp/anatomy]

Runs `uma bench mbc`'s own steps (`uma.bench.mbc`: tracking, the mirror's light and body
motion, the stream coded and decoded, the receiver's rendering; H.264 at its lowest rung from
`uma.bench.mbc_scores.codec_display`) and splits each frame's squared luma error inside the
face box by region, cut at the pose tracked on that frame (`uma.mbc.layers.cut_person`):
`eyes_mouth` (the eyes' and lips' feature points' hulls, widened), `face_mesh` (the rest of the
model's triangles), `head_ring` (the head ring beyond the mesh: forehead, hair, ears, neck),
`halo`, `torso` (the person below the head) and `background` (the rest of the box). Regions
follow the tracked pose, so where the pose is off they are off by as much.

Prints per clip and region: its share of the box's pixels, its MSE and PSNR for the MBC alone
(quantised), H.264 16k and the frozen display, and its part of the box's MSE (what it adds to
the box's error per box pixel); then the frames where the MBC loses most against H.264 with
the head's distance from frame 0's pose; writes those frames (source | MBC | H.264 | frozen,
then the MBC's and H.264's error x4, the regions) as PNGs under `--png-dir`.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
from pathlib import Path

import numpy as np

REGION_NAMES = ("eyes_mouth", "face_mesh", "head_ring", "halo", "torso", "background")
MOUTH = ("8.1", "8.2", "8.3", "8.4", "8.5", "8.6", "8.7", "8.8")
WIDEN_OF_FACE = 0.04  # the eyes' and mouth's hulls widened by this share of the face's width
DISPLAYS = ("mbc", "h264", "frozen")


def _hull(points: np.ndarray, shape, widen_px: int) -> np.ndarray:
    import cv2

    mask = np.zeros(shape, np.uint8)
    cv2.fillConvexPoly(mask, cv2.convexHull(np.rint(points).astype(np.int32)), 1)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * widen_px + 1,) * 2)
    return cv2.dilate(mask, kernel) > 0


def region_labels(renderer, params: np.ndarray, box) -> np.ndarray:
    """(H, W) int8: the index in `REGION_NAMES` of each pixel of the face box, -1 outside."""
    from uma.face.geometry import project
    from uma.face.render import triangle_labels
    from uma.mbc.layers import cut_person
    from uma.mbc.scene_render import HALO_OF_HEAD

    width, height = renderer.size
    model = renderer.description.model
    head, halo, torso, _ = cut_person(
        renderer.scene, renderer.scene.points(params), renderer.size, HALO_OF_HEAD
    )
    vertices = project(model, params)
    mesh = triangle_labels(vertices, model.triangles, (height, width)) >= 0
    widen = max(1, int(round(WIDEN_OF_FACE * np.ptp(vertices[:, 0]))))
    fp = model.feature_points
    parts = np.zeros((height, width), bool)
    parts |= _hull(vertices[[fp[n] for n in MOUTH if n in fp]], (height, width), widen)
    # Each eye separately (one hull over both would take the nose's bridge).
    for side in (("3.1", "3.3", "3.7", "3.11"), ("3.2", "3.4", "3.8", "3.12")):
        parts |= _hull(vertices[[fp[n] for n in side if n in fp]], (height, width), widen)
    labels = np.full((height, width), 5, np.int8)
    labels[torso > 0] = 4
    labels[halo > 0] = 3
    labels[head > 0] = 2
    labels[mesh] = 1
    labels[mesh & parts] = 0
    inside = np.zeros((height, width), bool)
    inside[box.y : box.y + box.height, box.x : box.x + box.width] = True
    labels[~inside] = -1
    return labels


def coded_run(clip, seed: int = 0):
    """The bench's steps on `clip`: (lumas, tracked results, units, the receiver, the decoded
    sets by frame, H.264 16k's display), as `uma bench mbc` runs them."""
    from uma.bench import mbc
    from uma.bench.mbc_scores import codec_display
    from uma.bench.mbc_stages import Clock, decode, encode
    from uma.config.codecs import MbcConfig
    from uma.mbc.stream import StreamConfig
    from uma.mbc.units import FaceUnits

    config = StreamConfig()
    lumas = [mbc._luma(f) for f in clip.frames]
    clock = Clock()
    results = mbc._track(clip, lumas, seed, None, clock)
    units = FaceUnits.of(clip.description.model, clip.description.params, light=True, body=True,
                         camera=mbc.CAMERA_MOTION)  # fmt: skip
    results[0] = mbc._as_decoded(results[0], units, config)
    *renderers, receiver, _scorer = mbc._renderers(clip, results, "picture", MbcConfig())
    coded = encode(lumas, results, units, config, renderers, clock)
    decoded, _ = decode(units, config, coded.packets, clock, coded.map_blocks)
    h264 = codec_display(clip.frames, clip.fps, 0, "h264")[0]
    return lumas, results, units, receiver, decoded, h264


def run(clip, png_dir: Path | None, worst: int, seed: int = 0) -> dict:
    """Per frame: region -> (pixels, squared error per display); per frame the head's
    distance from frame 0's pose (px)."""
    from uma.bench.mbc_scores import face_box

    lumas, results, units, receiver, decoded, h264 = coded_run(clip, seed)
    height = lumas[0].shape[0]
    shown, box, params = clip.frames[0], None, results[0].params
    frames = []
    for index in range(len(lumas)):
        if results[index]:
            params = results[index].params
        if index in decoded:
            p, light = units.split(decoded[index])
            shown, _ = receiver.render(p, light, units.body_of(decoded[index]))
        box = face_box(lumas[index], None, box)
        if index == 0 or box is None:
            continue
        labels = region_labels(receiver, params, box)
        truth = lumas[index].astype(np.float64)
        pictures = {"mbc": shown, "h264": h264[index], "frozen": clip.frames[0]}
        errors = {d: (truth - pictures[d][:height].astype(np.float64)) ** 2 for d in DISPLAYS}
        row = {"index": index, "box_px": int((labels >= 0).sum()),
               "moved_px": float(np.hypot(*(params[:2] - results[0].params[:2]))),
               "regions": {}}  # fmt: skip
        for k, name in enumerate(REGION_NAMES):
            where = labels == k
            row["regions"][name] = (int(where.sum()), {d: float(errors[d][where].sum())
                                                       for d in DISPLAYS})  # fmt: skip
        row["_pictures"] = (clip.frames[index], pictures, labels)
        frames.append(row)
    return {"frames": frames}


def _psnr(mse: float) -> float:
    return float(10 * np.log10(255.0**2 / max(mse, 1e-10)))


def report(name: str, frames: list[dict], png_dir: Path | None, worst: int) -> None:
    box_px = sum(f["box_px"] for f in frames)
    print(f"\n{name}: {len(frames)} frames, face box {box_px / len(frames):.0f} px a frame")
    print("region       share | MSE mbc / h264 / frozen | PSNR mbc / h264 / frozen | part of "
          "box MSE mbc / h264 (diff)")  # fmt: skip
    totals = {d: 0.0 for d in DISPLAYS}
    for region in REGION_NAMES:
        px = sum(f["regions"][region][0] for f in frames)
        sse = {d: sum(f["regions"][region][1][d] for f in frames) for d in DISPLAYS}
        for d in DISPLAYS:
            totals[d] += sse[d]
        mse = {d: sse[d] / max(px, 1) for d in DISPLAYS}
        part = {d: sse[d] / box_px for d in DISPLAYS}
        print(f"{region:12s} {px / box_px:5.3f} | {mse['mbc']:7.1f} / {mse['h264']:6.1f} / "
              f"{mse['frozen']:7.1f} | {_psnr(mse['mbc']):5.2f} / {_psnr(mse['h264']):5.2f} / "
              f"{_psnr(mse['frozen']):5.2f} | {part['mbc']:6.1f} / {part['h264']:5.1f} "
              f"({part['mbc'] - part['h264']:+6.1f})")  # fmt: skip
    print(f"{'box':12s} 1.000 | {totals['mbc'] / box_px:7.1f} / {totals['h264'] / box_px:6.1f} / "
          f"{totals['frozen'] / box_px:7.1f} | pooled PSNR {_psnr(totals['mbc'] / box_px):.2f} / "
          f"{_psnr(totals['h264'] / box_px):.2f} / {_psnr(totals['frozen'] / box_px):.2f}")  # fmt: skip
    _over_time(name, frames, png_dir, worst)


def _frame_psnr(f: dict, display: str) -> float:
    return _psnr(sum(r[1][display] for r in f["regions"].values()) / f["box_px"])


def _over_time(name: str, frames: list[dict], png_dir: Path | None, worst: int) -> None:
    gaps = np.array([_frame_psnr(f, "h264") - _frame_psnr(f, "mbc") for f in frames])
    moved = np.array([f["moved_px"] for f in frames])
    thirds = np.array_split(np.argsort(moved), 3)
    print("per-frame PSNR gap (h264 - mbc), dB: median {:.2f}, p90 {:.2f}, max {:.2f}; by the "
          "head's distance from frame 0 (thirds): {}".format(
              np.median(gaps), np.percentile(gaps, 90), gaps.max(),
              ", ".join(f"{moved[t].min():.1f}-{moved[t].max():.1f} px: {gaps[t].mean():.2f}"
                        for t in thirds)))  # fmt: skip
    print("frames by tenths: " + " ".join(f"{gaps[t].mean():.1f}"
                                          for t in np.array_split(np.arange(len(gaps)), 10)))  # fmt: skip
    for k in np.argsort(gaps)[::-1][:worst]:
        f = frames[k]
        regions = sorted(f["regions"].items(), key=lambda kv: kv[1][1]["h264"] - kv[1][1]["mbc"])
        top = ", ".join(f"{r} {(v[1]['mbc'] - v[1]['h264']) / f['box_px']:+.0f}"
                        for r, v in regions[:3])  # fmt: skip
        print(
            f"  frame {f['index']}: mbc {_frame_psnr(f, 'mbc'):.2f} h264 "
            f"{_frame_psnr(f, 'h264'):.2f} dB, moved {f['moved_px']:.1f} px; most: {top}"
        )
        if png_dir is not None:
            _save(png_dir / f"{name}-{f['index']:03d}.png", *f["_pictures"])


def _save(path: Path, source, pictures, labels) -> None:
    import cv2

    height = labels.shape[0]
    luma = [source[:height]] + [pictures[d][:height] for d in DISPLAYS]
    errs = [np.clip(4 * np.abs(source[:height].astype(int) - pictures[d][:height]), 0, 255)
            .astype(np.uint8) for d in ("mbc", "h264")]  # fmt: skip
    regions = ((labels.astype(int) + 1) * 36).astype(np.uint8)
    top = np.hstack(luma)
    bottom = np.hstack(errs + [regions, np.zeros_like(regions)])
    picture = np.vstack([top, bottom])
    path.parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(path), cv2.resize(picture, None, fx=2, fy=2, interpolation=cv2.INTER_NEAREST))


def main() -> None:
    from uma.bench.mbc_clips import default_clips

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--start", type=int, default=0)
    parser.add_argument("--frames", type=int, default=150)
    parser.add_argument("--clips", default="akiyo,carphone")
    parser.add_argument("--worst", type=int, default=3)
    parser.add_argument("--png-dir", type=Path, default=None)
    args = parser.parse_args()
    for clip in default_clips(args.frames, start=args.start):
        if clip.name not in args.clips.split(","):
            continue
        report(clip.name, run(clip, args.png_dir, args.worst)["frames"], args.png_dir,
               args.worst)  # fmt: skip


if __name__ == "__main__":
    main()
