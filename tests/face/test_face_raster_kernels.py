"""The compiled triangle fill draws exactly what OpenCV's fillPoly draws, triangle by triangle."""

from __future__ import annotations

import numpy as np
import pytest

from uma.face.render import triangle_labels

cv2 = pytest.importorskip("cv2")


def _opencv_labels(points, triangles, shape, order):
    labels = np.full(shape, -1, dtype=np.int32)
    polygons = np.round(points[triangles] * 16).astype(np.int32)
    for t in order:
        cv2.fillPoly(labels, [polygons[t]], int(t), lineType=cv2.LINE_8, shift=4)
    return labels


def _case(rng):
    height, width = int(rng.integers(5, 120)), int(rng.integers(5, 140))
    n = int(rng.integers(3, 40))
    if rng.random() < 0.5:  # small triangles (a mesh's), some reaching outside
        points = np.column_stack([rng.uniform(-3, width + 3, n), rng.uniform(-3, height + 3, n)])
    else:  # any size, near and far outside
        scale = float(rng.choice([0.05, 0.5, 1.5]))
        points = rng.uniform(-0.2 * width * scale, 1.2 * width * scale, (n, 2))
    if rng.random() < 0.3:  # on the pixel grid or its halves and sixteenths: ties
        grid = float(rng.choice([1, 2, 16]))
        points = np.round(points * grid) / grid
    triangles = rng.integers(0, n, (int(rng.integers(1, 50)), 3))
    return points, triangles, (height, width)


def test_fill_matches_opencv_fillpoly_on_random_triangles():
    rng = np.random.default_rng(20261203)
    for _ in range(600):
        points, triangles, shape = _case(rng)
        mask = rng.random(len(triangles)) < 0.8
        ours = triangle_labels(points, triangles, shape, triangle_mask=mask)
        order = np.arange(len(triangles))[mask]
        assert np.array_equal(ours, _opencv_labels(points, triangles, shape, order))


def test_fill_matches_opencv_in_depth_order():
    rng = np.random.default_rng(7)
    points, triangles, shape = _case(rng)
    depth = rng.normal(size=len(points))
    ours = triangle_labels(points, triangles, shape, depth=depth)
    order = np.argsort(depth[triangles].mean(axis=1), kind="stable")
    assert np.array_equal(ours, _opencv_labels(points, triangles, shape, order))


def test_fill_matches_opencv_on_a_long_thin_triangle():
    """OpenCV's edges run between the rounded vertices, not the sub-pixel ones: a long thin
    triangle's row ends there (one pixel apart here when the edge is taken sub-pixel)."""
    points = np.array([[0.0, 11.0], [314.5, 284.0], [66.5, 33.0]])
    triangles = np.array([[0, 1, 2]])
    ours = triangle_labels(points, triangles, (297, 321))
    assert np.array_equal(ours, _opencv_labels(points, triangles, (297, 321), [0]))


def test_a_wrong_fill_is_seen():
    """The comparison can fail: one pixel's label changed is a difference."""
    rng = np.random.default_rng(3)
    points = np.array([[2.3, 2.1], [30.7, 5.2], [12.4, 25.9]])
    triangles = np.array([[0, 1, 2]])
    ours = triangle_labels(points, triangles, (32, 32))
    assert np.array_equal(ours, _opencv_labels(points, triangles, (32, 32), [0]))
    ours[10, int(rng.integers(0, 32))] = 5
    assert not np.array_equal(ours, _opencv_labels(points, triangles, (32, 32), [0]))


def _numpy_barycentric_affine(points, triangles):
    """`barycentric_affine` as numpy computed it before it was compiled."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    v0, v1 = b - a, c - a
    det = v0[:, 0] * v1[:, 1] - v0[:, 1] * v1[:, 0]
    det = np.where(np.abs(det) < 1e-12, 1e-12, det)
    l1 = np.column_stack(
        [v1[:, 1] / det, -v1[:, 0] / det, (a[:, 1] * v1[:, 0] - a[:, 0] * v1[:, 1]) / det]
    )
    l2 = np.column_stack(
        [-v0[:, 1] / det, v0[:, 0] / det, (a[:, 0] * v0[:, 1] - a[:, 1] * v0[:, 0]) / det]
    )
    l0 = np.array([0.0, 0.0, 1.0]) - l1 - l2
    return np.stack([l0, l1, l2], axis=1)


@pytest.mark.parametrize("seed", range(4))
def test_barycentric_affine_equals_its_numpy_form_to_the_bit(seed):
    from uma.face.render import barycentric_affine

    rng = np.random.default_rng(seed)
    points = rng.uniform(-50, 400, (60, 2))
    points[5] = points[4]  # degenerate triangles (det 0) among them
    points[7] = points[4] + (1e-9, 0)
    triangles = rng.integers(0, 60, (200, 3)).astype(np.int32)
    triangles[0] = (4, 5, 6)
    triangles[1] = (4, 7, 6)
    got = barycentric_affine(points, triangles)
    want = _numpy_barycentric_affine(points, triangles)
    assert got.tobytes() == want.tobytes()
    assert barycentric_affine(points.astype(np.float32), triangles.astype(np.int64)).tobytes() == (
        _numpy_barycentric_affine(points.astype(np.float32).astype(np.float64), triangles).tobytes()
    )
