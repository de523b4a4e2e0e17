"""Compiled per-pixel steps of the plate's push-pull fill (`uma.mbc.layers.fill_unknown`;
numba).

Units: levels; planes float32 (the pyramid) and uint8 (the plate).

Each kernel does the numpy expressions it replaces with the same operations in the same order
and type (float32, no fused multiply-add), so the plate is the same to the bit
(`tests/mbc/test_fill_kernels.py` holds them to the numpy forms); one pass over the pixels
instead of a temporary array per operation.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["pull_level", "settle"]


@njit("void(float32[:, :], float32[:, :], float32[:, :], float32, float32[:, :])", cache=True)
def pull_level(values, weight, up, eps, out):
    """Into `out`: a pyramid level's own average where it knows something, the coarser level
    `up` (upsampled) where it does not: t (v / max(w, eps)) + (1 - t) up, t = clip(w, 0, 1)."""
    height, width = values.shape
    one = np.float32(1.0)
    zero = np.float32(0.0)
    for i in range(height):
        for j in range(width):
            w = weight[i, j]
            trust = min(max(w, zero), one)
            own = values[i, j] / max(w, eps)
            out[i, j] = trust * own + (one - trust) * up[i, j]


@njit("void(uint8[:, :], boolean[:, :], float32[:, :], uint8[:, :])", cache=True)
def settle(plane, known, filled, out):
    """Into `out`: `plane` where `known`, else `filled` rounded (half to even) and clipped to
    0-255."""
    height, width = plane.shape
    for i in range(height):
        for j in range(width):
            if known[i, j]:
                out[i, j] = plane[i, j]
            else:
                out[i, j] = np.uint8(min(max(np.rint(filled[i, j]), np.float32(0.0)),
                                         np.float32(255.0)))  # fmt: skip
