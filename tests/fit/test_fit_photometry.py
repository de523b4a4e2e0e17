"""The compiled photometric residual against the numpy formulation it replaced."""

from __future__ import annotations

import numpy as np
import pytest

from uma.fit.photometry import photometric_residual


def _numpy_residual(samples, values, tri, visible, n_tri, patch):
    s, t = samples[visible], values[visible]
    g = float(np.mean((s - s.mean()) * (t - t.mean())) / s.var())
    gain = np.full(samples.shape, g)
    offset = np.full(samples.shape, t.mean() - g * s.mean())
    if patch:
        idx = tri[visible]
        n = np.bincount(idx, minlength=n_tri).astype(np.float64)
        ss, st = np.bincount(idx, s, n_tri), np.bincount(idx, t, n_tri)
        sss, sst = np.bincount(idx, s * s, n_tri), np.bincount(idx, s * t, n_tri)
        with np.errstate(invalid="ignore", divide="ignore"):
            var, cov = sss - ss * ss / n, sst - ss * st / n
            patch_gain = cov / var
            usable = (n >= 8) & (var > 1e-3 * np.maximum(n, 1))
            usable &= (patch_gain > 0.2) & (patch_gain < 5.0)
            patch_offset = (st - patch_gain * ss) / n
        gain = np.where(usable[tri], patch_gain[tri], gain)
        offset = np.where(usable[tri], patch_offset[tri], offset)
    residual = gain * samples + offset - values
    return residual, gain, float(np.mean(residual[visible] ** 2))


@pytest.mark.parametrize("patch", [False, True])
def test_the_kernel_matches_numpy(patch: bool) -> None:
    rng = np.random.default_rng(3)
    k, n_tri = 3000, 40
    tri = rng.integers(0, n_tri, k)
    values = rng.uniform(20, 230, k)
    # Patches lit differently (gain and offset per triangle), one flat patch, noise.
    samples = values * rng.uniform(0.5, 1.5, n_tri)[tri] + rng.uniform(-20, 20, n_tri)[tri]
    samples[tri == 7] = 100.0
    samples += rng.normal(0, 2, k)
    visible = rng.random(k) > 0.2
    ok, residual, gain, error = photometric_residual(samples, values, tri, visible, n_tri, patch)
    want = _numpy_residual(samples, values, tri, visible, n_tri, patch)
    assert ok
    np.testing.assert_allclose(residual, want[0], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(gain, want[1], rtol=1e-9)
    assert error == pytest.approx(want[2], rel=1e-9)
    if patch:  # the per-patch light explains far more than one gain and offset
        _, _, _, global_error = photometric_residual(samples, values, tri, visible, n_tri, False)
        assert error < 0.5 * global_error


def test_a_flat_picture_or_too_few_pixels_is_not_ok() -> None:
    values = np.linspace(0, 100, 50)
    tri = np.zeros(50, np.int64)
    ok, *_ = photometric_residual(np.full(50, 9.0), values, tri, np.ones(50, bool), 1, False)
    assert not ok
    visible = np.zeros(50, bool)
    visible[:10] = True
    ok, *_ = photometric_residual(values.copy(), values, tri, visible, 1, False)
    assert not ok
