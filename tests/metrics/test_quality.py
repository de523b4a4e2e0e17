import numpy as np
import pytest

from uma.metrics.quality import PSNR_CAP_DB, psnr_db, ssim


def test_identical_planes():
    plane = np.random.default_rng(0).integers(0, 256, (64, 64), dtype=np.uint8)
    assert psnr_db(plane, plane) == PSNR_CAP_DB
    assert ssim(plane, plane) == pytest.approx(1.0)


def test_psnr_of_known_error():
    a = np.full((32, 32), 100, dtype=np.uint8)
    b = a + np.uint8(5)  # MSE 25
    assert psnr_db(a, b) == pytest.approx(10 * np.log10(255**2 / 25))


def test_ssim_falls_with_noise():
    rng = np.random.default_rng(1)
    plane = (rng.random((72, 88)) * 200).astype(np.uint8)
    light = np.clip(plane + rng.normal(0, 3, plane.shape), 0, 255).astype(np.uint8)
    heavy = np.clip(plane + rng.normal(0, 30, plane.shape), 0, 255).astype(np.uint8)
    assert 0 < ssim(plane, heavy) < ssim(plane, light) < 1


def test_shapes_must_match():
    with pytest.raises(ValueError):
        psnr_db(np.zeros((4, 4)), np.zeros((4, 5)))
