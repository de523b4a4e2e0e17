"""The face's light per frame, as the encoder measures it against the receiver's reference.

Units: gain unitless, offset in luma levels (BT.601 limited range).

The encoder renders what the receiver will show (`uma.mbc.scene_render.SceneRenderer`, the
same reference) and fits the frame's face luma as gain * rendered + offset by least squares
over the face's pixels. The result is clipped into the renderer's ranges, so a frame the fit
cannot explain (a flat face, a hand over it) never sends absurd light.
"""

from __future__ import annotations

import numpy as np

from uma.mbc.scene_render import LIGHT_GAIN_RANGE, LIGHT_OFFSET_RANGE

__all__ = ["estimate_light", "measure_light", "NEUTRAL_LIGHT"]

NEUTRAL_LIGHT = (1.0, 0.0)
_MIN_PIXELS = 64
_MIN_STD = 2.0  # levels: a flatter rendering says nothing about gain


def estimate_light(
    rendered: np.ndarray, actual: np.ndarray, mask: np.ndarray, *, every: int = 3
) -> tuple[float, float]:
    """(gain, offset) that best map `rendered`'s luma onto `actual`'s over `mask` (H, W),
    reading every `every`-th masked pixel; neutral where too few pixels or no contrast."""
    ys, xs = np.nonzero(mask)
    ys, xs = ys[::every], xs[::every]
    if ys.size < _MIN_PIXELS:
        return NEUTRAL_LIGHT
    r = rendered[ys, xs].astype(np.float64)
    a = actual[ys, xs].astype(np.float64)
    spread = r.std()
    if not np.isfinite(spread) or spread < _MIN_STD:
        return NEUTRAL_LIGHT
    gain = float(np.mean((r - r.mean()) * (a - a.mean())) / spread**2)
    gain = float(np.clip(gain, *LIGHT_GAIN_RANGE))
    offset = float(np.clip(a.mean() - gain * r.mean(), *LIGHT_OFFSET_RANGE))
    return gain, offset


def measure_light(renderer, luma: np.ndarray, params: np.ndarray) -> tuple[float, float]:
    """The light of the face at `params` on `luma` (H, W) against what `renderer` (a
    `SceneRenderer`, the receiver's reference) draws there."""
    patch, mask, (x0, y0) = renderer.face_luma(params)
    h, w = patch.shape
    return estimate_light(patch, luma[y0 : y0 + h, x0 : x0 + w], mask)
