"""`uma.fit.cost.batch_visible` (compiled) gives its numpy form's answer on every triangle."""

import numpy as np
import pytest

from uma.face.load import load_model
from uma.fit.cost import batch_visible


def _numpy_visible(triangles, points):
    a, b, c = points[:, triangles[:, 0]], points[:, triangles[:, 1]], points[:, triangles[:, 2]]
    cross = (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (
        c[..., 0] - a[..., 0]
    )
    return cross < 0


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_batch_visible_equals_the_numpy_cross_products(dtype):
    model = load_model()
    rng = np.random.default_rng(3)
    points = rng.normal(150, 60, (7, model.n_vertices, 2)).astype(dtype)
    points[2, :5] = points[2, 5]  # collinear and coincident vertices: cross exactly 0
    points[3, 0] = np.nan
    got = batch_visible(model, points)
    want = _numpy_visible(model.triangles, points)
    assert got.dtype == bool and got.shape == want.shape
    assert np.array_equal(got, want) and 0 < got.sum() < got.size
