"""The plate's band inpainted part by part is OpenCV's Telea over the whole picture, to the
bit."""

from __future__ import annotations

import numpy as np
import pytest

from uma.mbc.band_parts import band_boxes, inpaint_band
from uma.mbc.layers import EDGE_BAND_PX


def _band(known: np.ndarray) -> np.ndarray:
    import cv2

    kernel = np.ones((2 * EDGE_BAND_PX + 1, 2 * EDGE_BAND_PX + 1), np.uint8)
    return cv2.dilate(known.view(np.uint8), kernel) & ~known.view(np.uint8) & 1


def _scene(seed: int, height: int = 144, width: int = 176):
    """A textured plane and a known mask with one to four round holes, some at the edges."""
    rng = np.random.default_rng(seed)
    ys, xs = np.mgrid[0:height, 0:width]
    known = np.ones((height, width), bool)
    for _ in range(int(rng.integers(1, 5))):
        cx, cy, r = rng.integers(0, width), rng.integers(0, height), rng.integers(3, 40)
        known &= (xs - cx) ** 2 + (ys - cy) ** 2 > r * r
    plane = (80 + 60 * np.sin(xs / 5.0) * np.cos(ys / 7.0)).astype(np.uint8)
    plane += rng.integers(0, 30, (height, width), dtype=np.uint8)
    return plane, known


@pytest.mark.parametrize("seed", range(40))
def test_part_by_part_is_telea_over_the_whole_picture(seed: int) -> None:
    import cv2

    plane, known = _scene(seed)
    band = _band(known)
    whole = cv2.inpaint(plane, band, EDGE_BAND_PX, cv2.INPAINT_TELEA)
    assert np.array_equal(inpaint_band(plane, band, EDGE_BAND_PX), whole)


def test_background_on_either_side_of_a_person_is_two_parts() -> None:
    import cv2

    height, width = 288, 352
    plane, _ = _scene(1, height, width)
    known = np.zeros((height, width), bool)
    known[:260, :100] = known[:250, 260:] = True  # the background seen beside the person
    band = _band(known)
    assert len(band_boxes(band)) == 2
    whole = cv2.inpaint(plane, band, EDGE_BAND_PX, cv2.INPAINT_TELEA)
    assert np.array_equal(inpaint_band(plane, band, EDGE_BAND_PX), whole)
    known[100:110, 100:260] = True  # a bridge: one part
    assert len(band_boxes(_band(known))) == 1
    assert band_boxes(np.zeros_like(band)) == []
