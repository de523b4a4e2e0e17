"""The compiled SSIM map equals, bit for bit inside the window's border, the OpenCV box-filter
and NumPy array form it replaced (exact integer sums, each factor rounded once to float32)."""

from __future__ import annotations

import numpy as np
import pytest

from uma.metrics import quality
from uma.metrics.ssim_kernel import ssim_map_inside

cv2 = pytest.importorskip("cv2")
N, WINDOW, BORDER = quality._N, quality._WINDOW, quality._BORDER


def _array_form(ref: np.ndarray, tst: np.ndarray) -> np.ndarray:
    """The map as OpenCV's box filters and NumPy's steps computed it before the kernel."""

    def window_sum(plane):
        return cv2.boxFilter(plane, cv2.CV_32S, (WINDOW, WINDOW), normalize=False,
                             borderType=cv2.BORDER_REFLECT)  # fmt: skip

    sx, sy = window_sum(ref), window_sum(tst)
    sxx, syy, sxy = (
        window_sum(np.multiply(a, b, dtype=np.uint16))
        for a, b in ((ref, ref), (tst, tst), (ref, tst))
    )
    cross = sx * sy
    squares = sx * sx + sy * sy
    covariance = (sxy * N - cross) * 2
    variances = (sxx + syy) * N - squares
    c1, c2 = quality._C1 * N * N, quality._C2 * N * (N - 1)
    num = np.add(cross * 2, c1).astype(np.float32) * np.add(covariance, c2).astype(np.float32)
    den = np.add(squares, c1).astype(np.float32) * np.add(variances, c2).astype(np.float32)
    return num / den


def _pairs(rng):
    for case in range(150):
        height, width = int(rng.integers(7, 90)), int(rng.integers(7, 120))
        ref = rng.integers(0, 256, (height, width), dtype=np.uint8)
        if case % 3 == 0:
            tst = ref.copy()  # identical: exactly 1
        elif case % 3 == 1:
            noise = rng.integers(-12, 13, ref.shape)
            tst = np.clip(ref.astype(int) + noise, 0, 255).astype(np.uint8)
        else:
            tst = rng.integers(0, 256, ref.shape, dtype=np.uint8)
        yield ref, tst


def test_kernel_map_equals_the_array_form_bit_for_bit():
    rng = np.random.default_rng(20261203)
    for ref, tst in _pairs(rng):
        height, width = ref.shape
        inside = (slice(BORDER, height - BORDER), slice(BORDER, width - BORDER))
        expected = _array_form(ref, tst)[inside]
        got = quality._ssim_map_uint8(ref, tst)[inside]
        assert np.array_equal(got.view(np.uint32), expected.view(np.uint32))


def test_identical_planes_give_exactly_one_and_a_change_is_seen():
    rng = np.random.default_rng(1)
    ref = rng.integers(0, 256, (20, 30), dtype=np.uint8)
    out = np.zeros(ref.shape, np.float32)
    c1, c2 = quality._C1 * N * N, quality._C2 * N * (N - 1)
    assert np.all(ssim_map_inside(ref, ref, WINDOW, c1, c2, out)[3:-3, 3:-3] == 1.0)
    changed = ref.copy()
    changed[10, 15] ^= 0x40
    assert np.all(ssim_map_inside(ref, changed, WINDOW, c1, c2, out)[7:14, 12:19] < 1.0)
