"""SSIM's map of two uint8 planes in one compiled pass that runs without the GIL (numba).

Units: SSIM unitless; window sums in integer levels.

The same numbers as OpenCV's box filters and NumPy's array steps in `uma.metrics.quality`
(exact integer window sums, the covariances in integers, each factor rounded once from its
exact integer through float64 to float32, one float32 product each and one float32 division),
so every value of the map agrees to the bit; `tests/metrics/test_ssim_kernel.py` holds it to
that form. Only the map's inside is written: the window's 3-pixel border, which the means
leave out, is not. One call per plane pair instead of some twenty array steps, each of which
took and gave back the GIL: scoring threads no longer hold the simulation's thread up.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["ssim_map_inside"]


@njit(nogil=True, cache=True)
def _value(sx, sy, sxx, syy, sxy, n, c1, c2):
    """One pixel's SSIM from its window sums (N = n pixels), as the array steps compute it."""
    cross = sx * sy
    squares = sx * sx + sy * sy
    covariance = (sxy * n - cross) * 2
    variances = (sxx + syy) * n - squares
    num = np.float32(np.float64(cross * 2) + c1) * np.float32(np.float64(covariance) + c2)
    den = np.float32(np.float64(squares) + c1) * np.float32(np.float64(variances) + c2)
    return np.float32(num / den)


@njit(nogil=True, cache=True)
def _add_row(ref, tst, row, sign, cx, cy, cxx, cyy, cxy):
    """Add (sign 1) or take away (sign -1) row `row`'s values and products to the column sums."""
    for col in range(ref.shape[1]):
        x, y = np.int64(ref[row, col]), np.int64(tst[row, col])
        cx[col] += sign * x
        cy[col] += sign * y
        cxx[col] += sign * (x * x)
        cyy[col] += sign * (y * y)
        cxy[col] += sign * (x * y)


@njit(nogil=True, cache=True)
def ssim_map_inside(ref, tst, window, c1, c2, out):
    """SSIM's map of `ref` and `tst` (H, W) uint8 with a `window` x `window` uniform window
    into `out` (H, W) float32 at every pixel whose window lies inside the planes; `c1`, `c2`:
    the constants multiplied through as `uma.metrics.quality` does (C1 N^2, C2 N (N - 1))."""
    height, width = ref.shape
    half = window // 2
    n = window * window
    # each column's sums over the window's rows
    sums = np.zeros((5, width), np.int64)
    cx, cy, cxx, cyy, cxy = sums[0], sums[1], sums[2], sums[3], sums[4]
    for row in range(window - 1):
        _add_row(ref, tst, row, 1, cx, cy, cxx, cyy, cxy)
    for top in range(height - window + 1):
        _add_row(ref, tst, top + window - 1, 1, cx, cy, cxx, cyy, cxy)
        sx, sy = cx[:window].sum(), cy[:window].sum()
        sxx, syy, sxy = cxx[:window].sum(), cyy[:window].sum(), cxy[:window].sum()
        for left in range(width - window + 1):
            if left > 0:
                gone, new = left - 1, left + window - 1
                sx += cx[new] - cx[gone]
                sy += cy[new] - cy[gone]
                sxx += cxx[new] - cxx[gone]
                syy += cyy[new] - cyy[gone]
                sxy += cxy[new] - cxy[gone]
            out[top + half, left + half] = _value(sx, sy, sxx, syy, sxy, n, c1, c2)
        _add_row(ref, tst, top, -1, cx, cy, cxx, cyy, cxy)
    return out
