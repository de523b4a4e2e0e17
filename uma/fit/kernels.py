"""Compiled inner loops of the fitting cost (numba): project, cull, warp, sample and correlate.

Units: pixels, radians. For each candidate parameter set the model is deformed by its action
units, rotated (R = Rz Ry Rx), projected (weak perspective, as `uma.face.geometry.project`), its
back faces culled; then every template pixel moves with its triangle's vertices (barycentric
interpolation), the input image is sampled there bilinearly and the samples are correlated with
the template values, in one pass without temporaries. Outside the image the border pixel repeats
(as cv2.BORDER_REPLICATE). Doing the projection here too removes the ~100 us of numpy overhead
a batch that `project` + culling cost, more than scoring 2,000 pixels.

No `fastmath`: it lets LLVM reorder the sums to fill the CPU's vector width, so the same seed
gave other figures on a machine with other vector units (`docs/experiments.md`). In strict
order every sum is the same on any x86-64 machine.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "project_batch",
    "scores",
    "sample_at",
    "warp_jacobian",
    "front_facing",
    "MIN_PIXELS",
]

MIN_PIXELS = 16  # a candidate seeing fewer template pixels scores -1
MIN_PATCH_PIXELS = 4  # smaller patches are left out of the illumination-compensated score


@njit(cache=True)
def project_batch(vertices, units, params):
    """Projected vertices (B, N, 2) float32 of parameter sets (B, 6 + A)."""
    batch = params.shape[0]
    n_vertices = vertices.shape[0]
    n_units = units.shape[0]
    out = np.empty((batch, n_vertices, 2), dtype=np.float32)
    for b in range(batch):
        tx, ty, s = params[b, 0], params[b, 1], params[b, 2]
        cx, sx = np.cos(params[b, 3]), np.sin(params[b, 3])
        cy, sy = np.cos(params[b, 4]), np.sin(params[b, 4])
        cz, sz = np.cos(params[b, 5]), np.sin(params[b, 5])
        r00 = cz * cy
        r01 = cz * sy * sx - sz * cx
        r02 = cz * sy * cx + sz * sx
        r10 = sz * cy
        r11 = sz * sy * sx + cz * cx
        r12 = sz * sy * cx - cz * sx
        for n in range(n_vertices):
            x, y, z = vertices[n, 0], vertices[n, 1], vertices[n, 2]
            for a in range(n_units):
                w = params[b, 6 + a]
                if w != 0.0:
                    x += w * units[a, n, 0]
                    y += w * units[a, n, 1]
                    z += w * units[a, n, 2]
            out[b, n, 0] = tx + s * (r00 * x + r01 * y + r02 * z)
            out[b, n, 1] = ty - s * (r10 * x + r11 * y + r12 * z)
    return out


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def _bilinear_flat(flat, width, x, y):
    """`_bilinear` where x in [0, width - 1) and y in [0, height - 1), on the image's row-major
    pixels: no clamping, and one unsigned index spares the four 2-D index computations and
    numba's negative-index wrap-around checks."""
    x0 = int(x)
    y0 = int(y)
    fx = x - x0
    fy = y - y0
    i = np.uint64(y0 * width + x0)
    top = flat[i] * (1.0 - fx) + flat[i + np.uint64(1)] * fx
    bottom = flat[i + np.uint64(width)] * (1.0 - fx) + flat[i + np.uint64(width + 1)] * fx
    return top * (1.0 - fy) + bottom * fy


@njit(cache=True, inline="always")
def _inside(points, triangles, b, t, width, height):
    """Whether candidate b's triangle t lies where bilinear sampling needs no clamping."""
    for c in range(3):
        x = points[b, triangles[t, c], 0]
        y = points[b, triangles[t, c], 1]
        if not (0.0 <= x < width - 1.001 and 0.0 <= y < height - 1.001):
            return False
    return True


@njit(cache=True, inline="always")
def _warped_sample(image, corners, bary, points, b, k):
    """The image at template pixel k moved by candidate b's vertices."""
    i, j, m = corners[k, 0], corners[k, 1], corners[k, 2]
    x = bary[k, 0] * points[b, i, 0] + bary[k, 1] * points[b, j, 0] + bary[k, 2] * points[b, m, 0]
    y = bary[k, 0] * points[b, i, 1] + bary[k, 1] * points[b, j, 1] + bary[k, 2] * points[b, m, 1]
    return _bilinear(image, x, y)


@njit(cache=True)
def _front_facing(points, triangles, b, out):
    """Triangles of candidate b that face the camera (clockwise in image coordinates)."""
    for t in range(triangles.shape[0]):
        i, j, m = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        ax, ay = points[b, i, 0], points[b, i, 1]
        cross = (points[b, j, 0] - ax) * (points[b, m, 1] - ay) - (points[b, j, 1] - ay) * (
            points[b, m, 0] - ax
        )
        out[t] = cross < 0.0


@njit(cache=True)
def sample_at(image, corners, bary, points):
    """Samples of `image` at the template pixels moved to `points` (B, N, 2) -> (B, K)."""
    batch = points.shape[0]
    count = corners.shape[0]
    out = np.empty((batch, count), dtype=np.float32)
    for b in range(batch):
        for k in range(count):
            out[b, k] = _warped_sample(image, corners, bary, points, b, k)
    return out


@njit(cache=True, inline="always")
def _affine(points, triangles, inverse, b, t, out):
    """The affine map (2, 3) taking template pixel (x, y, 1) of triangle t to candidate b."""
    i, j, m = triangles[t, 0], triangles[t, 1], triangles[t, 2]
    for row in range(2):
        p0, p1, p2 = points[b, i, row], points[b, j, row], points[b, m, row]
        for col in range(3):
            out[row, col] = (
                p0 * inverse[t, 0, col] + p1 * inverse[t, 1, col] + p2 * inverse[t, 2, col]
            )


# Long on purpose (86 lines): one pass per candidate over every template pixel with running
# sums in registers; split into helpers, numba would keep the sums in arrays between calls.
@njit(cache=True)
def scores(image, pixels, inverse, runs, template, points, triangles, patch_weight):
    """Correlation of the template with the image warped by each candidate (B,) in [-1, 1].

    The template pixels (x, y) are grouped by triangle: run r covers pixels runs[r, 1] to
    runs[r, 2] of triangle runs[r, 0] (each triangle in one run). Within a triangle the warp is
    affine: `inverse[t]` (3, 3) takes the triangle's template vertices [x; y; 1] to barycentric
    weights, so the candidate's vertices give the map once per triangle, not per pixel. Only
    triangles facing the camera count.
    The plain score is the normalised correlation coefficient over their pixels. The
    illumination-compensated score normalises each triangle patch to zero mean and unit
    variance in both images and takes the pixel-weighted mean of the per-patch correlations, so
    a gain and offset per patch changes nothing; patches under MIN_PATCH_PIXELS pixels or flat
    are left out. The result is (1 - patch_weight) * plain + patch_weight * compensated. A
    candidate seeing fewer than MIN_PIXELS pixels, or a flat image, scores -1.
    """
    batch = points.shape[0]
    n_tri = triangles.shape[0]
    out = np.empty(batch, dtype=np.float64)
    visible = np.empty(n_tri, dtype=np.bool_)
    warp = np.empty((2, 3), dtype=np.float64)
    height, width = image.shape
    flat = image.ravel()  # a view: the costs' images are C-contiguous
    for b in range(batch):
        _front_facing(points, triangles, b, visible)
        n = 0.0
        s_s = 0.0
        s_t = 0.0
        s_ss = 0.0
        s_tt = 0.0
        s_st = 0.0
        total = 0.0
        weight = 0.0
        for r in range(runs.shape[0]):
            if not visible[runs[r, 0]]:
                continue
            _affine(points, triangles, inverse, b, runs[r, 0], warp)
            a00, a01, a02 = warp[0, 0], warp[0, 1], warp[0, 2]
            a10, a11, a12 = warp[1, 0], warp[1, 1], warp[1, 2]
            p_s = 0.0
            p_t = 0.0
            p_ss = 0.0
            p_tt = 0.0
            p_st = 0.0
            inside = _inside(points, triangles, b, runs[r, 0], width, height)
            for k in range(runs[r, 1], runs[r, 2]):
                u, v = pixels[k, 0], pixels[k, 1]
                x = a00 * u + a01 * v + a02
                y = a10 * u + a11 * v + a12
                s = _bilinear_flat(flat, width, x, y) if inside else _bilinear(image, x, y)
                t = template[k]
                p_s += s
                p_t += t
                p_ss += s * s
                p_tt += t * t
                p_st += s * t
            m = float(runs[r, 2] - runs[r, 1])
            n += m
            s_s += p_s
            s_t += p_t
            s_ss += p_ss
            s_tt += p_tt
            s_st += p_st
            if patch_weight <= 0.0 or m < MIN_PATCH_PIXELS:
                continue
            cov = p_st - p_s * p_t / m
            var_s = p_ss - p_s * p_s / m
            var_t = p_tt - p_t * p_t / m
            if var_s <= 1e-6 * m or var_t <= 1e-6 * m:
                continue
            total += m * cov / np.sqrt(var_s * var_t)
            weight += m
        plain = -1.0
        if n >= MIN_PIXELS:
            cov = s_st - s_s * s_t / n
            var_s = s_ss - s_s * s_s / n
            var_t = s_tt - s_t * s_t / n
            if var_s > 1e-6 * n and var_t > 1e-6 * n:
                plain = cov / np.sqrt(var_s * var_t)
        compensated = total / weight if weight >= MIN_PIXELS else -1.0
        if patch_weight <= 0.0:
            out[b] = plain
        elif patch_weight >= 1.0:
            out[b] = compensated
        else:
            out[b] = (1.0 - patch_weight) * plain + patch_weight * compensated
    return out


@njit(cache=True)
def warp_jacobian(grad_x, grad_y, corners, bary, points, d_points, gain, rows):
    """The Jacobian (R, P) of the gain-scaled warped image with respect to the parameters, at
    the template pixels `rows` (R,) only (the fit's visible ones: the others' rows would be
    computed and dropped).

    J[r, p] = gain[k] * (grad_x(W_k) * dW_k/dp_x + grad_y(W_k) * dW_k/dp_y), with k = rows[r],
    W_k the warped position of template pixel k (barycentric in `points` (1, N, 2)) and dW_k/dp
    barycentric in the vertex derivatives `d_points` (P, N, 2); the gradient images are sampled
    bilinearly at W_k. J^T J and J^T r then go through BLAS.
    """
    n_params = d_points.shape[0]
    out = np.empty((rows.shape[0], n_params), dtype=np.float64)
    for r in range(rows.shape[0]):
        k = rows[r]
        gx = _warped_sample(grad_x, corners, bary, points, 0, k) * gain[k]
        gy = _warped_sample(grad_y, corners, bary, points, 0, k) * gain[k]
        i, j, m = corners[k, 0], corners[k, 1], corners[k, 2]
        wi, wj, wm = bary[k, 0], bary[k, 1], bary[k, 2]
        for p in range(n_params):
            dx = wi * d_points[p, i, 0] + wj * d_points[p, j, 0] + wm * d_points[p, m, 0]
            dy = wi * d_points[p, i, 1] + wj * d_points[p, j, 1] + wm * d_points[p, m, 1]
            out[r, p] = gx * dx + gy * dy
    return out


@njit(cache=True)
def front_facing(points, triangles, out):
    """Into `out` (B, T) bool: whether each candidate's triangle faces the camera, as
    `uma.fit.cost.batch_visible`'s numpy form computes it (the cross product in the points'
    own type, in its order; no fast-math, no fused multiply-add: the same to the bit)."""
    for b in range(points.shape[0]):
        for t in range(triangles.shape[0]):
            i, j, m = triangles[t, 0], triangles[t, 1], triangles[t, 2]
            ax, ay = points[b, i, 0], points[b, i, 1]
            cross = (points[b, j, 0] - ax) * (points[b, m, 1] - ay) - (points[b, j, 1] - ay) * (
                points[b, m, 0] - ax
            )
            out[b, t] = cross < 0
