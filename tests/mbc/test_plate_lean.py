"""The plate's never-seen luma leaned toward the blurred reference, blurred over a box only."""

import numpy as np
import pytest

from uma.mbc import plate_lean


@pytest.mark.parametrize("size", [(176, 144), (352, 288)])
def test_the_lean_over_the_unknown_box_is_the_whole_pictures(size) -> None:
    """Blurred over the unknown pixels' box and the blur's reach only, the lean is to the bit
    the one over a whole-picture blur, boxes at the picture's edges included (fails if the
    reach is cut below OpenCV's kernel, e.g. 2 sigma)."""
    import cv2

    width, height = size
    rng = np.random.default_rng(width)
    for _ in range(40):
        reference = rng.integers(0, 256, (height, width), dtype=np.uint8)
        filled = rng.integers(0, 256, (height, width), dtype=np.uint8)
        known = np.ones((height, width), bool)
        y0, y1 = sorted(rng.integers(0, height, 2))
        x0, x1 = sorted(rng.integers(0, width, 2))
        known[y0 : y1 + 1, x0 : x1 + 1] = rng.random((y1 + 1 - y0, x1 + 1 - x0)) < 0.3
        got = filled.copy()
        plate_lean.lean_on_reference(got, reference, known)
        share = plate_lean.REFERENCE_OF_FILL
        blurred = cv2.GaussianBlur(reference, (0, 0), plate_lean.REFERENCE_BLUR_PX)
        want = filled.copy()
        mixed = (1.0 - share) * filled[~known] + share * blurred[~known]
        want[~known] = np.rint(mixed).astype(np.uint8)
        assert np.array_equal(got, want)


def test_nothing_unknown_changes_nothing() -> None:
    filled = np.full((16, 16), 77, np.uint8)
    plate_lean.lean_on_reference(filled, np.zeros_like(filled), np.ones((16, 16), bool))
    assert np.all(filled == 77)
