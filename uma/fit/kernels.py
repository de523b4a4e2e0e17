"""Compiled inner loops of the fitting cost (numba): warp, bilinear sample and correlate.

Units: pixels. For each candidate parameter set the template pixels move with the projected
vertices (barycentric interpolation), the input image is sampled there bilinearly, and the
samples are correlated with the template values, in one pass and without temporaries:
~4,500 pixels a candidate cost tens of microseconds instead of the ~125 us of numpy + remap.
Outside the image the border pixel repeats (as cv2.BORDER_REPLICATE).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["ncc_scores", "patch_ncc_scores", "sample_at"]


@njit(cache=True, fastmath=True, inline="always")
def _bilinear(image, x, y):
    height, width = image.shape
    if x < 0.0:
        x = 0.0
    elif x > width - 1.0:
        x = width - 1.0
    if y < 0.0:
        y = 0.0
    elif y > height - 1.0:
        y = height - 1.0
    x0 = int(x)
    y0 = int(y)
    x1 = min(x0 + 1, width - 1)
    y1 = min(y0 + 1, height - 1)
    fx = x - x0
    fy = y - y0
    top = image[y0, x0] * (1.0 - fx) + image[y0, x1] * fx
    bottom = image[y1, x0] * (1.0 - fx) + image[y1, x1] * fx
    return top * (1.0 - fy) + bottom * fy


@njit(cache=True, fastmath=True, inline="always")
def _warped_sample(image, corners, bary, points, b, k):
    """The image at template pixel k moved by candidate b's vertices."""
    i, j, m = corners[k, 0], corners[k, 1], corners[k, 2]
    x = bary[k, 0] * points[b, i, 0] + bary[k, 1] * points[b, j, 0] + bary[k, 2] * points[b, m, 0]
    y = bary[k, 0] * points[b, i, 1] + bary[k, 1] * points[b, j, 1] + bary[k, 2] * points[b, m, 1]
    return _bilinear(image, x, y)


@njit(cache=True, fastmath=True)
def sample_at(image, corners, bary, points):
    """Samples of `image` at the template pixels moved to `points` (B, N, 2) -> (B, K)."""
    batch = points.shape[0]
    count = corners.shape[0]
    out = np.empty((batch, count), dtype=np.float32)
    for b in range(batch):
        for k in range(count):
            out[b, k] = _warped_sample(image, corners, bary, points, b, k)
    return out


@njit(cache=True, fastmath=True)
def ncc_scores(image, corners, bary, tri, template, points, visible):
    """Normalised correlation coefficient of template and warped image over visible pixels.

    `visible` (B, T) says which triangles face the camera for each candidate. Returns (B,)
    scores in [-1, 1]; a candidate seeing fewer than 16 pixels, or a flat patch, scores -1.
    """
    batch = points.shape[0]
    count = corners.shape[0]
    scores = np.empty(batch, dtype=np.float64)
    for b in range(batch):
        n = 0
        s_s = 0.0
        s_t = 0.0
        s_ss = 0.0
        s_tt = 0.0
        s_st = 0.0
        for k in range(count):
            if not visible[b, tri[k]]:
                continue
            s = _warped_sample(image, corners, bary, points, b, k)
            t = template[k]
            n += 1
            s_s += s
            s_t += t
            s_ss += s * s
            s_tt += t * t
            s_st += s * t
        if n < 16:
            scores[b] = -1.0
            continue
        cov = s_st - s_s * s_t / n
        var_s = s_ss - s_s * s_s / n
        var_t = s_tt - s_t * s_t / n
        if var_s <= 1e-6 or var_t <= 1e-6:
            scores[b] = -1.0
        else:
            scores[b] = cov / np.sqrt(var_s * var_t)
    return scores


@njit(cache=True, fastmath=True)
def patch_ncc_scores(image, corners, bary, tri, template, points, visible, n_triangles):
    """Correlation after normalising each triangle patch to zero mean and unit variance in both
    images (illumination compensation): the pixel-weighted mean of per-patch correlations,
    invariant to a gain and offset per patch. Patches under 4 pixels or flat are skipped."""
    batch = points.shape[0]
    count = corners.shape[0]
    scores = np.empty(batch, dtype=np.float64)
    acc = np.zeros((n_triangles, 6), dtype=np.float64)
    for b in range(batch):
        acc[:, :] = 0.0
        for k in range(count):
            j = tri[k]
            if not visible[b, j]:
                continue
            s = _warped_sample(image, corners, bary, points, b, k)
            t = template[k]
            acc[j, 0] += 1.0
            acc[j, 1] += s
            acc[j, 2] += t
            acc[j, 3] += s * s
            acc[j, 4] += t * t
            acc[j, 5] += s * t
        total = 0.0
        weight = 0.0
        for j in range(n_triangles):
            n = acc[j, 0]
            if n < 4.0:
                continue
            cov = acc[j, 5] - acc[j, 1] * acc[j, 2] / n
            var_s = acc[j, 3] - acc[j, 1] * acc[j, 1] / n
            var_t = acc[j, 4] - acc[j, 2] * acc[j, 2] / n
            if var_s <= 1e-6 or var_t <= 1e-6:
                continue
            total += n * cov / np.sqrt(var_s * var_t)
            weight += n
        scores[b] = total / weight if weight >= 16.0 else -1.0
    return scores
