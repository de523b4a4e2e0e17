"""`uma.mbc.layered_kernels` gives the numpy forms it replaces to the bit."""

import numpy as np
import pytest

from uma.mbc.layered_kernels import FAR_OUTSIDE_MAP, STILL_MAP, affine_maps, blend, triangle_maps


def _numpy_maps(labels, table, empty, xs, ys):
    rows = table.T
    flat = np.where(labels < 0, empty, labels).ravel()
    c = [np.take(row, flat).reshape(labels.shape) for row in rows]
    return c[0] * xs + c[1] * ys + c[2], c[3] * xs + c[4] * ys + c[5]


def _numpy_blend(top, toward, weight):
    where = np.nonzero(weight != 0)
    a = top[where].astype(np.float32)
    b = toward[where].astype(np.float32)
    top[where] = np.clip(np.rint(a + weight[where] * (b - a)), 0, 255)


@pytest.mark.parametrize("seed", range(5))
def test_affine_maps_equal_the_numpy_gathers(seed):
    rng = np.random.default_rng(seed)
    height, width, n_tri = 60, 44, 30
    ys, xs = np.mgrid[0:100, 0:80].astype(np.float32)
    xs, ys = xs[7 : 7 + height, 11 : 11 + width], ys[7 : 7 + height, 11 : 11 + width]
    labels = rng.integers(-1, n_tri, (height, width)).astype(np.int32)
    table = rng.normal(0, 3, (n_tri + 1, 6)).astype(np.float32) * [1, 1, 40, 1, 1, 40]
    table = table.astype(np.float32)
    map_x, map_y = np.empty((height, width), np.float32), np.empty((height, width), np.float32)
    affine_maps(labels, table, n_tri, xs, ys, map_x, map_y)
    want_x, want_y = _numpy_maps(labels, table, n_tri, xs, ys)
    assert map_x.dtype == want_x.dtype == np.float32
    assert map_x.tobytes() == want_x.tobytes() and map_y.tobytes() == want_y.tobytes()


@pytest.mark.parametrize("seed", range(5))
def test_blend_equals_the_numpy_form_on_strided_views(seed):
    rng = np.random.default_rng(seed)
    picture = rng.integers(0, 256, (80, 90), dtype=np.uint8)
    toward = rng.integers(0, 256, (80, 90), dtype=np.uint8)
    weight = (0.9 * rng.random((80, 90))).astype(np.float32)
    weight[rng.random((80, 90)) < 0.4] = 0.0
    weight[0, :5] = (0.5, 1.0, -0.0, 1e-8, 0.49999997)
    got, want = picture.copy(), picture.copy()
    # The views the renderer blends: a box of the picture, chroma's every other pixel.
    blend(got[10:70:2, 5:85], toward[10:70:2, 5:85], weight[::2, :80][:30])
    _numpy_blend(want[10:70:2, 5:85], toward[10:70:2, 5:85], weight[::2, :80][:30])
    assert got.tobytes() == want.tobytes()
    assert not np.array_equal(got, picture)


@pytest.mark.parametrize("outside", [STILL_MAP, FAR_OUTSIDE_MAP])
def test_triangle_maps_read_outside_through_its_own_map(outside):
    rng = np.random.default_rng(7)
    height, width, n_tri = 30, 24, 12
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    labels = rng.integers(-1, n_tri, (height, width)).astype(np.int32)
    coeffs = rng.normal(0, 2, (n_tri, 2, 3))
    map_x, map_y = triangle_maps(labels, coeffs, outside, xs, ys)
    table = np.concatenate([coeffs, np.array(outside)[None]]).reshape(-1, 6).astype(np.float32)
    want_x, want_y = _numpy_maps(labels, table, n_tri, xs, ys)
    assert map_x.tobytes() == want_x.tobytes() and map_y.tobytes() == want_y.tobytes()
    off = labels < 0
    assert off.any()
    if outside is STILL_MAP:  # a pixel outside every triangle reads where it is
        assert np.array_equal(map_x[off], xs[off]) and np.array_equal(map_y[off], ys[off])
    else:
        assert (map_x[off] < -1e3).all() and (map_y[off] < -1e3).all()


@pytest.mark.parametrize("seed", range(4))
def test_relight_equals_the_numpy_form_on_a_strided_box(seed):
    from uma.mbc.layered_kernels import relight

    rng = np.random.default_rng(seed)
    picture = rng.integers(0, 256, (50, 60), dtype=np.uint8)
    outside = rng.uniform(0, 12, (40, 44)).astype(np.float32)
    outside[:10] = 0.0  # the face itself
    feather, gain, offset = np.float32(6.0), 1.0 + rng.uniform(-0.7, 2.5), rng.uniform(-60, 60)
    want = picture.copy()
    box = want[5:45, 9:53]
    weight = np.clip(1.0 - outside / feather, 0.0, 1.0)
    a = box.astype(np.float32)
    lit = a + weight * (a * np.float32(gain - 1.0) + np.float32(offset))
    box[:] = np.clip(np.rint(lit), 0, 255).astype(np.uint8)
    relight(picture[5:45, 9:53], outside, feather, np.float32(gain - 1.0), np.float32(offset))
    assert np.array_equal(picture, want)
