"""Compiled per-pixel steps of the talking head's rendering (numba).

Each computes exactly what the numpy expressions it replaces computed, in the same float32
operations and order (no fused multiply-add: numba's default keeps IEEE rounding), so a seed
renders the same bytes; `tests/face/test_face_talking_head.py` holds them to the numpy forms. They
only save the numpy forms' temporaries: the (height, width, 3, 3) gather of each pixel's
triangle coefficients and the products built from it.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["pixel_maps", "light_and_noise"]


@njit(cache=True)
def pixel_maps(coeffs: np.ndarray, labels: np.ndarray) -> tuple:
    """Per pixel (x, y): `coeffs[labels[y, x]] @ (x, y, 1)`, as float32 maps (map x, map y,
    light factor), each row of `coeffs` (triangles + 1, 3, 3) float32 and -1 the last."""
    height, width = labels.shape
    last = coeffs.shape[0] - 1
    map_x = np.empty((height, width), np.float32)
    map_y = np.empty((height, width), np.float32)
    light = np.empty((height, width), np.float32)
    for row in range(height):
        y = np.float32(row)
        for col in range(width):
            x = np.float32(col)
            label = labels[row, col]
            c = coeffs[last if label < 0 else label]
            map_x[row, col] = c[0, 0] * x + c[0, 1] * y + c[0, 2]
            map_y[row, col] = c[1, 0] * x + c[1, 1] * y + c[1, 2]
            light[row, col] = c[2, 0] * x + c[2, 1] * y + c[2, 2]
    return map_x, map_y, light


@njit(cache=True)
def light_and_noise(
    sampled: np.ndarray, light: np.ndarray, gain: np.float32, noise: np.ndarray,
    noise_std: np.float32,
) -> np.ndarray:  # fmt: skip
    """uint8 `clip(rint(sampled * (gain * light) + noise_std * noise))` per channel, the
    products in float32 (`noise` may be empty: no noise)."""
    height, width, channels = sampled.shape
    out = np.empty((height, width, channels), np.uint8)
    noisy = noise.size > 0
    for row in range(height):
        for col in range(width):
            factor = gain * light[row, col]
            for ch in range(channels):
                value = np.float32(sampled[row, col, ch]) * factor
                if noisy:
                    value = value + noise_std * noise[row, col, ch]
                value = np.rint(value)
                out[row, col, ch] = 0 if value < 0 else (255 if value > 255 else np.uint8(value))
    return out
