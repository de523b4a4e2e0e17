"""Whether a coded refresh is worth more than what the receiver renders: the engine's judge.

Units: luma PSNR in dB over the refresh's box (BT.601 limited-range levels); pictures planar
YUV 4:2:0 (H * 3 // 2, W) uint8.

Judging a refresh is the only time the engine's mirror (its copy of the receiver's
`uma.mbc.scene_render.SceneRenderer`) draws a whole picture; every other frame it draws only
the face's luma (to measure light). `needs_judging` says when the answer cannot change what the
engine does, so the caller skips that drawing: with no threshold to meet, or before the first
refresh when the first is always sent. `refresh_gain_db` is the judgement itself, shared by
the simulation and `uma bench mbc`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["needs_judging", "refresh_gain_db", "residual_gain_db", "box_psnr_db"]


def needs_judging(min_gain_db: float, *, first_always: bool, refresh_taken: bool) -> bool:
    """Whether the engine needs a refresh's gain to decide on it: not when every refresh is
    sent whatever its gain (`min_gain_db` is minus infinity), nor for the first one when the
    first is always sent (`first_always` and no refresh taken yet)."""
    if math.isinf(min_gain_db) and min_gain_db < 0:
        return False
    return not (first_always and not refresh_taken)


def box_psnr_db(picture: np.ndarray, truth: np.ndarray) -> float:
    """Luma PSNR (dB) of `picture` against `truth`, same shape; 100 for identical ones.
    Two uint8 pictures' squared errors are summed as integers: the float64 mean of the same
    integers is exact too, so the value is the same to the bit, at a third of the cost."""
    if picture.dtype == truth.dtype == np.uint8 and picture.shape == truth.shape:
        diff = np.subtract(picture, truth, dtype=np.int32)
        np.multiply(diff, diff, out=diff)  # at most 255 ** 2 a pixel
        mse = int(diff.sum(dtype=np.int64)) / diff.size if diff.size else float("nan")
    else:
        mse = float(np.mean((picture.astype(np.float64) - truth.astype(np.float64)) ** 2))
    return 100.0 if mse <= 1e-10 else 10.0 * math.log10(255.0**2 / mse)


def refresh_gain_db(
    mirror, units, values: np.ndarray, corner: tuple[int, int], patch: np.ndarray,
    truth: np.ndarray,
) -> float:  # fmt: skip
    """How much better (dB) the decoded refresh box `patch` (YUV 4:2:0, its corner (x0, y0) in
    the picture) is than `mirror`'s rendering at the decoded set `values` (`units`'
    `uma.mbc.units.FaceUnits` layout), both against `truth` (the source picture, YUV 4:2:0),
    over the box's luma."""
    params, light = units.split(values)
    rendered, _ = mirror.render(params, light, units.body_of(values), luma_only=True)
    height = rendered.shape[0] * 2 // 3
    x0, y0 = corner
    box_h = patch.shape[0] * 2 // 3
    window = (slice(y0, y0 + box_h), slice(x0, x0 + patch.shape[1]))
    truth_box = truth[:height][window]
    return box_psnr_db(patch[:box_h], truth_box) - box_psnr_db(rendered[:height][window], truth_box)


def residual_gain_db(base: np.ndarray, refresh, truth: np.ndarray) -> float:
    """How much better (dB) the box a decoded residual `refresh` (`uma.mbc.refresh_coder.
    ResidualBox`) composes on `base` (the rendering it was coded against, YUV 4:2:0 at the
    source size) is than `base` there, both against `truth` (the source picture), over the
    box's luma."""
    from uma.mbc.refresh_coder import residual_patch

    patch = residual_patch(base, refresh)
    (box_w, box_h), (x0, y0) = refresh.box, refresh.corner
    window = (slice(y0, y0 + box_h), slice(x0, x0 + box_w))
    height = base.shape[0] * 2 // 3
    truth_box = truth[:height][window]
    return box_psnr_db(patch[:box_h], truth_box) - box_psnr_db(base[:height][window], truth_box)
