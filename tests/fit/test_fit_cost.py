"""The fitting cost: exact at the template, invariant to light as specified, kernels = numpy."""

import numpy as np
import pytest

from uma.face.geometry import project
from uma.fit import Cost
from uma.fit.kernels import project_batch


def _patchwise(fit, rng):
    """The template image with a random gain and offset on each triangle patch."""
    gains = rng.uniform(0.4, 1.6, len(fit.model.triangles))
    offsets = rng.uniform(-50, 50, len(fit.model.triangles))
    image = fit.image.copy()
    r = fit.raster
    image[r.ys, r.xs] = fit.image[r.ys, r.xs] * gains[r.tri] + offsets[r.tri]
    return image


def test_cost_is_zero_at_the_template_pose_and_counts(template):
    fit = template.fit
    cost = Cost(fit, fit.image)
    assert float(cost(fit.params)) == pytest.approx(0.0, abs=1e-5)
    shifted = np.repeat(fit.params[None], 3, axis=0)
    shifted[1, 0] += 2.0
    shifted[2, 4] += 0.1
    values = cost(shifted)
    assert values.shape == (3,) and values[0] == pytest.approx(0.0, abs=1e-5)
    assert np.all(values[1:] > 0.01)
    assert cost.evaluations == 4


def test_plain_cost_ignores_one_gain_and_offset(template):
    fit = template.fit
    cost = Cost(fit, 0.5 * fit.image + 40.0)
    assert float(cost(fit.params)) == pytest.approx(0.0, abs=1e-5)


def test_illumination_compensation_ignores_gain_and_offset_per_patch(template):
    fit = template.fit
    image = _patchwise(fit, np.random.default_rng(3))
    assert float(Cost(fit, image, illumination=True)(fit.params)) == pytest.approx(0.0, abs=1e-4)
    assert float(Cost(fit, image)(fit.params)) > 0.05
    # Away from the pose the compensated score still sees the misalignment.
    moved = fit.params.copy()
    moved[1] += 2.0
    assert float(Cost(fit, image, illumination=True)(moved)) > 0.05


def test_a_weight_mixes_the_two_scores(template):
    fit = template.fit
    image = _patchwise(fit, np.random.default_rng(4))
    moved = fit.params + np.r_[1.0, -1.0, 0.0, 0.05, 0.0, 0.0, np.zeros(fit.params.size - 6)]
    batch = np.stack([fit.params, moved])
    plain, compensated = Cost(fit, image)(batch), Cost(fit, image, illumination=True)(batch)
    mixed = Cost(fit, image, illumination=0.25)(batch)
    assert np.allclose(mixed, 0.75 * plain + 0.25 * compensated)
    with pytest.raises(ValueError):
        Cost(fit, image, illumination=1.5)


def test_compiled_projection_matches_the_geometry(template):
    model = template.fit.model
    rng = np.random.default_rng(0)
    params = (
        template.fit.params
        + rng.normal(0, 1, (6, template.fit.params.size))
        * np.r_[5, 5, 3, 0.3, 0.3, 0.3, np.full(model.n_actions, 0.5)]
    )
    fast = project_batch(model.vertices, model.action_units, params)
    assert np.allclose(fast, project(model, params), atol=1e-3)


def test_bad_candidates_cost_the_most(template):
    fit = template.fit
    cost = Cost(fit, fit.image)
    far = fit.params.copy()
    far[:2] += 10_000.0  # every pixel samples the replicated border: a flat patch
    nan = fit.params.copy()
    nan[3] = np.nan
    values = cost(np.stack([fit.params, far, nan]))
    assert values[0] == pytest.approx(0.0, abs=1e-5)
    assert values[1] == 2.0 and values[2] == 2.0
    with pytest.raises(ValueError):
        cost(fit.params[:5])


def test_blur_and_thinning_keep_the_minimum(template):
    fit = template.fit
    coarse = Cost(fit, fit.image, blur_px=2.0).thinned(500)
    assert 400 < coarse.pixels <= 500
    assert float(coarse(fit.params)) == pytest.approx(0.0, abs=1e-5)
    moved = fit.params.copy()
    moved[0] += 1.0
    assert float(coarse(moved)) > 0.0


def _shaded(image: np.ndarray, strength: float) -> np.ndarray:
    """`image` lit from the side: a gain rising smoothly from left to right (1 - s to 1 + s)."""
    ramp = np.linspace(1.0 - strength, 1.0 + strength, image.shape[1], dtype=np.float32)
    return image * ramp[None, :]


def test_band_pass_of_the_log_image_keeps_the_minimum_and_cancels_shading(template):
    from uma.fit.cost import prepared

    fit = template.fit
    band = Cost(fit, fit.image, blur_px=1.5, band_px=4.0)
    assert float(band(fit.params)) == pytest.approx(0.0, abs=1e-5)
    moved = fit.params.copy()
    moved[0] += 1.5
    assert float(band(moved)) > 0.01
    # A smooth side light (gain 0.3 to 1.7 across the picture) moves the plain cost at the true
    # pose far more than the band-passed one, where it becomes a near-constant offset.
    lit = _shaded(fit.image, 0.7)
    plain = float(Cost(fit, lit, blur_px=1.5)(fit.params))
    banded = float(Cost(fit, lit, blur_px=1.5, band_px=4.0)(fit.params))
    assert banded < 0.25 * plain
    with pytest.raises(ValueError):
        prepared(fit.image, 2.0, 1.0)  # the band must be wider than the blur
    flat = prepared(np.full((40, 40), 7.0, np.float32), 1.0, 3.0)
    assert np.allclose(flat, 0.0, atol=1e-4)
