"""Compiled photometric residual of one Gauss-Newton evaluation (numba).

Units: grey levels. Given the picture sampled at the template's warped pixels, the template's
values, each pixel's triangle and whether it faces the camera: the least-squares gain and
offset that map the samples onto the template over the visible pixels (one for the picture,
or one per triangle patch where the patch allows), the residual gain * sample + offset -
template at every pixel and its mean square over the visible ones. The same arithmetic as
numpy's `mean`/`var`/`bincount` formulation it replaces (about a tenth of its time: that one
spent most of it in numpy's call overhead on a few thousand pixels).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["photometric_residual", "MIN_VISIBLE"]

MIN_VISIBLE = 16  # fewer visible pixels: nothing to compare
_FLAT = 1e-6  # a standard deviation below this (grey levels): nothing to compare
_PATCH_MIN = 8  # a patch needs this many visible pixels for its own gain and offset
_PATCH_GAIN = (0.2, 5.0)  # a patch gain outside this keeps the picture's


@njit(cache=True)
def _global(samples, values, visible):
    """(ok, gain, offset) over the visible pixels."""
    n, ss, tt = 0, 0.0, 0.0
    for i in range(samples.size):
        if visible[i]:
            n += 1
            ss += samples[i]
            tt += values[i]
    if n < MIN_VISIBLE:
        return False, 0.0, 0.0
    ms, mt = ss / n, tt / n
    vs, vt, cst = 0.0, 0.0, 0.0
    for i in range(samples.size):
        if visible[i]:
            ds, dt = samples[i] - ms, values[i] - mt
            vs += ds * ds
            vt += dt * dt
            cst += ds * dt
    vs, vt, cst = vs / n, vt / n, cst / n
    if np.sqrt(vs) < _FLAT or np.sqrt(vt) < _FLAT:
        return False, 0.0, 0.0
    gain = cst / vs
    return True, gain, mt - gain * ms


@njit(cache=True)
def _patches(samples, values, tri, visible, n_tri, gain, offset):
    """Each usable patch's own gain and offset into `gain` and `offset` (in place)."""
    n = np.zeros(n_tri)
    ss, st, sss, sst = np.zeros(n_tri), np.zeros(n_tri), np.zeros(n_tri), np.zeros(n_tri)
    for i in range(samples.size):
        if visible[i]:
            t, s, v = tri[i], samples[i], values[i]
            n[t] += 1.0
            ss[t] += s
            st[t] += v
            sss[t] += s * s
            sst[t] += s * v
    usable = np.zeros(n_tri, np.bool_)
    patch_gain, patch_offset = np.zeros(n_tri), np.zeros(n_tri)
    for t in range(n_tri):
        if n[t] < _PATCH_MIN:
            continue
        var = sss[t] - ss[t] * ss[t] / n[t]
        cov = sst[t] - ss[t] * st[t] / n[t]
        if not var > 1e-3 * n[t]:
            continue
        g = cov / var
        if _PATCH_GAIN[0] < g < _PATCH_GAIN[1]:
            usable[t] = True
            patch_gain[t], patch_offset[t] = g, (st[t] - g * ss[t]) / n[t]
    for i in range(samples.size):
        if usable[tri[i]]:
            gain[i], offset[i] = patch_gain[tri[i]], patch_offset[tri[i]]


@njit(cache=True)
def photometric_residual(samples, values, tri, visible, n_tri, patch):
    """(ok, residual (K,), gain (K,), mean squared residual over the visible pixels); not ok
    when too few pixels are visible or either side is flat."""
    k = samples.size
    residual, gain = np.zeros(k), np.zeros(k)
    ok, g, o = _global(samples, values, visible)
    if not ok:
        return False, residual, gain, np.inf
    gain[:] = g
    offset = np.full(k, o)
    if patch:
        _patches(samples, values, tri, visible, n_tri, gain, offset)
    total, count = 0.0, 0
    for i in range(k):
        residual[i] = gain[i] * samples[i] + offset[i] - values[i]
        if visible[i]:
            total += residual[i] * residual[i]
            count += 1
    return True, residual, gain, total / count
