"""Compiled per-pixel steps of the block map (`uma.mbc.block_map`; numba).

Units: pixels; pictures uint8; errors and weights float32.

Each kernel gives what the numpy expression it replaces gives, to the bit: a block's squared
error is a sum of 64 integer squares under 2**24, exact in float32 in any order; the blend does
the same float32 operations in the same order, one pass instead of a temporary array each.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["block_sse", "accumulate"]


@njit("void(uint8[:, :], uint8[:, :], int64, float32[:, :])", cache=True)
def block_sse(candidate, truth, block, out):
    """Into `out` (rows, cols): each `block`-pixel square block's sum of squared differences
    between `candidate` and `truth` (rows * block, cols * block)."""
    rows, cols = out.shape
    for r in range(rows):
        for c in range(cols):
            total = np.int64(0)
            for i in range(r * block, (r + 1) * block):
                for j in range(c * block, (c + 1) * block):
                    d = np.int64(candidate[i, j]) - np.int64(truth[i, j])
                    total += d * d
            out[r, c] = np.float32(total)


@njit("void(float32[:, :], float32[:, :], uint8[:, :], float32[:, :])", cache=True)
def accumulate(mixed, base, candidate, weight):
    """`mixed` (in place) += `weight` * (`candidate` - `base`), in float32."""
    height, width = mixed.shape
    for i in range(height):
        for j in range(width):
            mixed[i, j] += weight[i, j] * (np.float32(candidate[i, j]) - base[i, j])
