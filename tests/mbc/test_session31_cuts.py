"""Session 31's exact cuts give what the plain calls give: the halo's dilation over the raised
head's box, weights zeroed by OpenCV's masked copy, the head's chroma maps in place, and the
block map's ranked gains."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from uma.mbc.layer_boxes import dilated
from uma.mbc.layered_kernels import half_map, zero_where


@pytest.mark.parametrize("seed", range(6))
def test_the_dilation_over_the_mask_s_box_is_the_whole_picture_s(seed):
    """Random masks (at the picture's edges too, or empty) and elliptic kernels: the same
    as dilating the whole picture."""
    rng = np.random.default_rng(seed)
    shape = (144, 176)
    mask = np.zeros(shape, np.uint8)
    if seed:
        x0, y0 = int(rng.integers(-30, 170)), int(rng.integers(-30, 140))
        box = mask[max(y0, 0) : max(y0, 0) + 60, max(x0, 0) : max(x0, 0) + 50]
        box[:] = rng.random(box.shape) < 0.6
    radius = int(rng.integers(3, 15))
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1))
    np.testing.assert_array_equal(dilated(mask, kernel, radius), cv2.dilate(mask, kernel))


def test_weights_zeroed_by_the_masked_copy_are_the_boolean_index_s():
    rng = np.random.default_rng(4)
    weight = rng.random((40, 52)).astype(np.float32) - np.float32(0.1)
    where = np.zeros((60, 80), bool)
    where[10:50, 20:72] = rng.random((40, 52)) < 0.5
    expected = weight.copy()
    expected[where[10:50, 20:72]] = 0.0
    zero_where(weight, where[10:50, 20:72])  # a view, as the drawing's masks are
    np.testing.assert_array_equal(weight, expected)
    assert not np.signbit(weight[where[10:50, 20:72]]).any()


def test_the_chroma_maps_in_place_are_numpy_s_expression():
    rng = np.random.default_rng(5)
    full = (rng.random((64, 90)) * 400 - 50).astype(np.float32)
    expected = (full[0::2, 0::2] + full[1::2, 1::2] - 1.0) * 0.25
    got = half_map(full)
    assert got.dtype == np.float32
    np.testing.assert_array_equal(got, expected)


def test_the_ranked_gains_are_the_loop_s():
    """The blocks that gain, most first, ties in index order, as the list loop ranked them."""
    rng = np.random.default_rng(6)
    gain = rng.integers(-3, 4, 256).astype(np.float32)
    gain[:5] = np.inf
    gain[5] = np.nan
    expected = [k for k in np.argsort(-gain, kind="stable") if gain[k] > 0]
    ranked = np.argsort(-gain, kind="stable")
    assert ranked[gain[ranked] > 0].tolist() == [int(k) for k in expected]
