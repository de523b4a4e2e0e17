"""Compiled per-pixel steps of the layered rendering (`uma.mbc.layered_render`; numba).

Units: pixels; maps float32; pictures uint8.

Each kernel does the numpy expression it replaces with the same operations in the same
order and type (float32, no fused multiply-add: numba's default keeps IEEE rounding), so
the pictures are the same to the bit (`tests/mbc/test_layered_kernels.py` holds them to the
numpy forms); one pass over the pixels instead of a temporary array per operation.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "affine_maps",
    "blend",
    "copy_where",
    "zero_where",
    "relight",
    "relight_face",
    "triangle_maps",
    "STILL_MAP",
    "FAR_OUTSIDE_MAP",
]

STILL_MAP = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0))  # a pixel reads where it is
FAR_OUTSIDE_MAP = ((-1e4, -1e4, -1e4), (-1e4, -1e4, -1e4))  # far outside any picture


# One signature each, compiled (or loaded from the cache) on import: boxes of the picture are
# C-contiguous or strided as they fall, and would each compile their own layout.
@njit(
    "void(int32[:, :], float32[:, :], int64, float32[:, :], float32[:, :], float32[:, :],"
    " float32[:, :])",
    cache=True,
)
def affine_maps(labels, table, empty, xs, ys, map_x, map_y):
    """Into `map_x`, `map_y` (H, W) float32: where each pixel reads, `table[t]` (6,) float32
    being the affine map (x, y) of its triangle t = `labels` (H, W) (row `empty` where the
    label is negative) at the pixel's (`xs`, `ys`): c0 x + c1 y + c2, c3 x + c4 y + c5."""
    height, width = labels.shape
    for i in range(height):
        row, row_x, row_y, out_x, out_y = labels[i], xs[i], ys[i], map_x[i], map_y[i]
        last = -1  # read at the first pixel whatever its label
        c0 = c1 = c2 = c3 = c4 = c5 = np.float32(0.0)
        for j in range(width):
            t = row[j]
            if j == 0 or t != last:  # a row's pixels come in runs of one triangle: read once
                last = t
                if t < 0:
                    t = empty
                c0, c1, c2 = table[t, 0], table[t, 1], table[t, 2]
                c3, c4, c5 = table[t, 3], table[t, 4], table[t, 5]
            x = row_x[j]
            y = row_y[j]
            out_x[j] = c0 * x + c1 * y + c2
            out_y[j] = c3 * x + c4 * y + c5


@njit("void(uint8[:, :], uint8[:, :], float32[:, :])", cache=True)
def blend(top, toward, weight):
    """`top` (uint8, in place) moved toward `toward` by `weight` (float32; 0: unchanged):
    rint(a + w (b - a)) clipped to 0-255, in float32."""
    height, width = top.shape
    for i in range(height):
        for j in range(width):
            w = weight[i, j]
            if w != 0:
                a = np.float32(top[i, j])
                b = np.float32(toward[i, j])
                value = np.rint(a + w * (b - a))
                if value < 0:
                    value = np.float32(0)
                elif value > 255:
                    value = np.float32(255)
                top[i, j] = np.uint8(value)


@njit("void(uint8[:, :], float32[:, :], float32, float32, float32)", cache=True)
def relight(box, outside_px, feather, gain_less_one, offset):
    """`box` (uint8, in place) relit with a weight fading from 1 at the face to 0 `feather`
    pixels out (`outside_px` (float32) the distance from the face): a + clip(1 - d / feather,
    0, 1) (a (gain - 1) + offset), rounded and clipped to 0-255, in float32."""
    height, width = box.shape
    for i in range(height):
        for j in range(width):
            weight = np.float32(1.0) - outside_px[i, j] / feather
            weight = min(max(weight, np.float32(0.0)), np.float32(1.0))
            a = np.float32(box[i, j])
            value = np.rint(a + weight * (a * gain_less_one + offset))
            if value < 0:
                value = np.float32(0)
            elif value > 255:
                value = np.float32(255)
            box[i, j] = np.uint8(value)


def triangle_maps(labels, coeffs, outside, xs, ys) -> tuple[np.ndarray, np.ndarray]:
    """(map_x, map_y) (H, W) float32 for `cv2.remap`: where each pixel of `labels` (H, W) int32
    reads, through its triangle's affine map `coeffs[t]` (T, 2, 3) of the pixel's (`xs`, `ys`),
    or through `outside` (2, 3) where the label is -1 (float64 maps, rounded to float32 once)."""
    outside = np.asarray(outside, dtype=np.float64).reshape(1, 2, 3)
    table = np.concatenate([coeffs, outside]).reshape(-1, 6).astype(np.float32)
    map_x = np.empty(labels.shape, np.float32)
    map_y = np.empty(labels.shape, np.float32)
    affine_maps(labels, table, len(coeffs), xs, ys, map_x, map_y)
    return map_x, map_y


def relight_face(
    luma: np.ndarray, face: np.ndarray, light: tuple[float, float], feather_of_face: float
) -> None:
    """The face's pixels of `luma` (in place) times the gain plus the offset, over the face's
    box only; with `feather_of_face` (`uma.mbc.scene_render.LIGHT_FEATHER_OF_FACE`), the light fades out over that share of the face's
    width beyond its edge (a relit face beside a head ring that is not shows a step where the
    mesh ends: a seam across the hair)."""
    import cv2

    x, y, w, h = cv2.boundingRect(face.view(np.uint8))
    if w == 0 or h == 0:
        return
    gain, offset = light
    feather = int(round(feather_of_face * w))
    if feather < 1:
        box, inside = luma[y : y + h, x : x + w], face[y : y + h, x : x + w]
        lit = box[inside].astype(np.float32) * gain + offset
        box[inside] = np.clip(np.rint(lit), 0, 255).astype(np.uint8)
        return
    height, width = luma.shape
    x0, y0 = max(x - feather, 0), max(y - feather, 0)
    x1, y1 = min(x + w + feather, width), min(y + h + feather, height)
    inside = face[y0:y1, x0:x1]
    outside_px = cv2.distanceTransform((~inside).view(np.uint8), cv2.DIST_L2, 3)
    steps = np.float32(feather), np.float32(gain - 1.0), np.float32(offset)
    relight(luma[y0:y1, x0:x1], outside_px, *steps)  # a + w (a (gain - 1) + offset), compiled


def copy_where(dst: np.ndarray, src: np.ndarray, mask: np.ndarray) -> None:
    """`np.copyto(dst, src, where=mask)` (pictures or weights of one dtype; `mask` bool or 0/1
    uint8) by OpenCV's vectorised masked copy, in place (numpy's where= copy costs several
    times more)."""
    import cv2

    if cv2.copyTo(src, mask.view(np.uint8), dst) is not dst:  # a new array: copy it back
        np.copyto(dst, src, where=mask.view(bool))


def zero_where(weight: np.ndarray, where: np.ndarray) -> None:
    """`weight[where] = 0.0` (float32 weights, `where` bool of its shape) by OpenCV's masked
    copy of zeros, in place: the same weights at about half the boolean index's cost."""
    copy_where(weight, np.zeros_like(weight), where)
