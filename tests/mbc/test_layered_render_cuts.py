"""The layered drawing's exact cuts give what the plain calls give (session 29): the gap closed
over the person's box only, and OpenCV's masked copy in place of numpy's."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from uma.mbc.layered_kernels import copy_where as _copy_where
from uma.mbc.layered_render import _GAP_KERNEL, _close_gap


def _blob(rng: np.random.Generator, shape, box) -> np.ndarray:
    x0, y0, x1, y1 = box
    mask = np.zeros(shape, np.uint8)
    mask[y0:y1, x0:x1] = rng.random((y1 - y0, x1 - x0)) < 0.5
    return mask


@pytest.mark.parametrize("box", [(30, 20, 70, 60), (0, 0, 25, 18), (80, 50, 100, 72), None])
def test_the_gap_closed_over_the_person_s_box_is_the_whole_picture_s(box):
    """Random head and halo in a box (at a corner, at the far edge, or none at all): the same
    as dilating the whole picture, grown pixels on the head's own taken off."""
    rng = np.random.default_rng(7)
    shape = (72, 100)
    if box is None:
        head = halo = np.zeros(shape, np.uint8)
    else:
        head, halo = _blob(rng, shape, box), _blob(rng, shape, box)
    expected = cv2.dilate(halo | head, _GAP_KERNEL) & (1 - head)
    np.testing.assert_array_equal(_close_gap(halo, head), expected)


@pytest.mark.parametrize("mask_dtype", [bool, np.uint8])
def test_the_masked_copy_writes_into_a_view_as_numpy_s_where_copy(mask_dtype):
    """Into a slice of a bigger picture (not contiguous), where the mask is set only."""
    rng = np.random.default_rng(3)
    picture = rng.integers(0, 256, (60, 80), np.uint8)
    expected = picture.copy()
    src = rng.integers(0, 256, (20, 30), np.uint8)
    mask = (rng.random((20, 30)) < 0.4).astype(mask_dtype)
    np.copyto(expected[10:30, 40:70], src, where=mask.astype(bool))
    _copy_where(picture[10:30, 40:70], src, mask)
    np.testing.assert_array_equal(picture, expected)
