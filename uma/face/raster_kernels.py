"""Compiled triangle filling (numba): OpenCV's `fillPoly` of one triangle at a time, exactly.

Units: pixels; vertices in 1/16 pixel (int32, `fillPoly`'s `shift=4`).

`fill_triangles` draws what `cv2.fillPoly(labels, [polygon], t, lineType=cv2.LINE_8, shift=4)`
draws for each triangle in turn, without a call into OpenCV per triangle: OpenCV's scan-line
fill (edges between the rounded vertices in 16.16 fixed point, a row's span from the
ceiling of its left edge to the floor of its right edge) and the 8-connected Bresenham outline it draws along each edge between the
rounded vertices. It handles only triangles whose rounded vertices all lie inside the picture
(OpenCV clips the others, and so changes its edges): it stops at the first other one and
returns its position, for the caller to draw that one with OpenCV and go on. `tests/face/
test_face_raster_kernels.py` holds it to OpenCV on random triangles, inside and out.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["fill_triangles", "barycentric_rows"]

_SHIFT = 16  # OpenCV's XY_SHIFT: edges in 16.16 fixed point
_ONE = 1 << _SHIFT


@njit(cache=True)
def _line(labels, x0, y0, x1, y1, value):
    """OpenCV's 8-connected line from (x0, y0) to (x1, y1), drawn left to right."""
    if x1 < x0:
        x0, y0, x1, y1 = x1, y1, x0, y0
    dx = x1 - x0
    dy = y1 - y0
    sy = 1
    if dy < 0:
        dy, sy = -dy, -1
    x, y = x0, y0
    if dy > dx:
        err = dy - (dx + dx)
        for _ in range(dy + 1):
            labels[y, x] = value
            if err < 0:
                x += 1
                err += dy + dy
            err -= dx + dx
            y += sy
    else:
        err = dx - (dy + dy)
        for _ in range(dx + 1):
            labels[y, x] = value
            if err < 0:
                y += sy
                err += dx + dx
            err -= dy + dy
            x += 1


@njit(cache=True)
def _inside(polygon, height, width):
    """Whether every vertex of `polygon` (3, 2), rounded as OpenCV rounds it, is a pixel."""
    for j in range(3):
        x = ((np.int64(polygon[j, 0]) << 12) + (_ONE >> 1)) >> _SHIFT
        y = (np.int64(polygon[j, 1]) + 8) >> 4
        if x < 0 or x >= width or y < 0 or y >= height:
            return False
    return True


@njit(cache=True)
def _edges(labels, polygon, value, ex, edx, ey0, ey1):
    """Draw the outline and collect the non-horizontal edges (start x, slope, rows); count."""
    n = 0
    for j in range(3):
        i = (j + 2) % 3
        x0 = np.int64(polygon[i, 0]) << 12
        y0 = (np.int64(polygon[i, 1]) + 8) >> 4
        x1 = np.int64(polygon[j, 0]) << 12
        y1 = (np.int64(polygon[j, 1]) + 8) >> 4
        # OpenCV's edges run between the rounded vertices, as its outline does.
        x0 = ((x0 + (_ONE >> 1)) >> _SHIFT) << _SHIFT
        x1 = ((x1 + (_ONE >> 1)) >> _SHIFT) << _SHIFT
        _line(labels, x0 >> _SHIFT, y0, x1 >> _SHIFT, y1, value)
        if y0 == y1:
            continue
        num, den = x1 - x0, y1 - y0
        step = abs(num) // abs(den)  # C's division: towards zero
        edx[n] = -step if (num < 0) != (den < 0) else step
        if y0 < y1:
            ey0[n], ey1[n], ex[n] = y0, y1, x0
        else:
            ey0[n], ey1[n], ex[n] = y1, y0, x1
        n += 1
    return n


@njit(cache=True)
def fill_triangles(labels, polygons, order, start):
    """Draw triangles `polygons[order[k]]` (T, 3, 2) into `labels` (H, W) int32, each with its
    number, for k from `start`; returns the first k whose triangle is not wholly inside the
    picture (or len(order): all drawn)."""
    height, width = labels.shape
    ex = np.empty(3, np.int64)
    edx = np.empty(3, np.int64)
    ey0 = np.empty(3, np.int64)
    ey1 = np.empty(3, np.int64)
    for k in range(start, order.shape[0]):
        t = order[k]
        if not _inside(polygons[t], height, width):
            return k
        n = _edges(labels, polygons[t], t, ex, edx, ey0, ey1)
        if n < 2:
            continue
        top, bottom = ey0[0], ey1[0]
        for j in range(1, n):
            top, bottom = min(top, ey0[j]), max(bottom, ey1[j])
        for y in range(top, min(bottom, height)):
            # The row's span between the edges that cross it (inline: a call per row costs
            # more than the row).
            lo = hi = np.int64(0)
            seen = 0
            for j in range(n):
                if ey0[j] <= y < ey1[j]:
                    x = ex[j] + (y - ey0[j]) * edx[j]
                    lo = x if seen == 0 else min(lo, x)
                    hi = x if seen == 0 else max(hi, x)
                    seen += 1
            first, last = (lo + _ONE - 1) >> _SHIFT, hi >> _SHIFT
            if seen < 2 or first >= width or last < 0:
                continue
            for x in range(max(first, 0), min(last, width - 1) + 1):
                labels[y, x] = t
    return order.shape[0]


@njit(cache=True)
def barycentric_rows(points, triangles, out):
    """Into `out` (T, 3, 3): `uma.face.render.barycentric_affine`'s rows, with its numpy
    form's operations in its order (float64, no fused multiply-add), so the same to the bit."""
    for t in range(triangles.shape[0]):
        i, j, m = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        ax, ay = points[i, 0], points[i, 1]
        v0x, v0y = points[j, 0] - ax, points[j, 1] - ay
        v1x, v1y = points[m, 0] - ax, points[m, 1] - ay
        det = v0x * v1y - v0y * v1x
        if abs(det) < 1e-12:
            det = 1e-12
        l1x, l1y, l1c = v1y / det, -v1x / det, (ay * v1x - ax * v1y) / det
        l2x, l2y, l2c = -v0y / det, v0x / det, (ax * v0y - ay * v0x) / det
        out[t, 0, 0] = (0.0 - l1x) - l2x
        out[t, 0, 1] = (0.0 - l1y) - l2y
        out[t, 0, 2] = (1.0 - l1c) - l2c
        out[t, 1, 0], out[t, 1, 1], out[t, 1, 2] = l1x, l1y, l1c
        out[t, 2, 0], out[t, 2, 1], out[t, 2, 2] = l2x, l2y, l2c
