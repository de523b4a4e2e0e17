import numpy as np
import pytest

from uma.bench.init_cases import _astronaut_template, make_cases
from uma.face import load_model
from uma.fit import (
    AnnealingSchedule,
    Cost,
    SaabsConfig,
    anneal,
    fit_face,
    mde_px,
    metropolis_accept,
    saabs,
    search_box,
)
from uma.fit.cost import FitTemplate


@pytest.fixture(scope="module")
def template():
    return _astronaut_template(load_model())


@pytest.fixture(scope="module")
def cases(template):
    return make_cases([template], 3, rng=11)


def test_metropolis_rule():
    assert metropolis_accept(-0.1, 0.01, 0.999)
    assert metropolis_accept(0.0, 0.0, 0.5)
    assert not metropolis_accept(0.01, 0.0, 0.0)
    # A worse proposal is accepted with probability exp(-delta / T).
    p = np.exp(-0.02 / 0.01)
    assert metropolis_accept(0.02, 0.01, p - 1e-9)
    assert not metropolis_accept(0.02, 0.01, p + 1e-9)
    rng = np.random.default_rng(0)
    accepted = np.mean([metropolis_accept(0.02, 0.01, rng.random()) for _ in range(20000)])
    assert abs(accepted - p) < 0.01


def test_schedule_cools_from_initial_to_final():
    schedule = AnnealingSchedule(steps=11, initial_temperature=0.1, final_temperature=0.001)
    assert 0.1 * schedule.cooling**10 == pytest.approx(0.001)
    with pytest.raises(ValueError):
        AnnealingSchedule(steps=0)


def test_cost_is_zero_at_the_template_pose(template):
    fit = template.fit
    cost = Cost(fit, fit.image)
    assert float(cost(fit.params)) == pytest.approx(0.0, abs=1e-5)
    shifted = fit.params.copy()
    shifted[0] += 3.0
    assert float(cost(shifted)) > 0.01
    assert cost.evaluations == 2


def test_illumination_compensation_ignores_gain_and_offset_per_patch(template):
    fit = template.fit
    rng = np.random.default_rng(3)
    gains = rng.uniform(0.5, 1.5, len(fit.model.triangles))
    offsets = rng.uniform(-40, 40, len(fit.model.triangles))
    image = fit.image.copy()
    r = fit.raster
    image[r.ys, r.xs] = fit.image[r.ys, r.xs] * gains[r.tri] + offsets[r.tri]
    compensated = Cost(fit, image, illumination=True)
    plain = Cost(fit, image)
    assert float(compensated(fit.params)) == pytest.approx(0.0, abs=1e-4)
    assert float(plain(fit.params)) > 0.05


def test_saabs_recovers_a_known_pose(template, cases):
    model = template.fit.model
    errors = []
    for seed, case in enumerate(cases):
        start = template.fit.params
        box = search_box(start, template.fit.face_width_px)
        result = saabs(Cost(template.fit, case.image.astype(np.float32)), start, box, rng=seed)
        errors.append(mde_px(model, result.params, case.truth))
        assert (
            result.evaluations
            <= SaabsConfig().global_phase.budget + SaabsConfig().local_phase.budget + 3
        )
    start_errors = [mde_px(model, template.fit.params, c.truth) for c in cases]
    assert np.median(errors) < 1.5
    assert np.median(errors) < 0.3 * np.median(start_errors)


def test_hybrid_is_precise(template, cases):
    model = template.fit.model
    errors = []
    for seed, case in enumerate(cases):
        box = search_box(template.fit.params, template.fit.face_width_px)
        result = fit_face(
            template.fit,
            case.image.astype(np.float32),
            method="hybrid",
            start=template.fit.params,
            box=box,
            rng=seed,
        )
        assert result
        errors.append(mde_px(model, result.params, case.truth))
    assert np.median(errors) < 0.6


def test_same_generator_same_fit(template, cases):
    case = cases[0]
    box = search_box(template.fit.params, template.fit.face_width_px)
    a = saabs(Cost(template.fit, case.image.astype(np.float32)), template.fit.params, box, rng=7)
    b = saabs(Cost(template.fit, case.image.astype(np.float32)), template.fit.params, box, rng=7)
    assert np.array_equal(a.params, b.params)


def test_anneal_stays_in_the_box(template):
    fit = template.fit
    box = search_box(fit.params, fit.face_width_px)
    steps = np.full(fit.params.size, 5.0)
    best, _, _, _ = anneal(
        Cost(fit, fit.image),
        fit.params,
        box,
        steps,
        AnnealingSchedule(steps=5),
        rng=np.random.default_rng(0),
        active=np.ones(fit.params.size, bool),
    )
    assert box.contains(best)


@pytest.mark.parametrize(
    "image, reason",
    [
        (np.full((112, 92), 128, np.float32), "flat"),
        (np.where(np.arange(92) % 2, 255, 0) * np.ones((112, 1), np.float32), "saturated"),
        (np.full((8, 8), 1, np.float32), "at least 16x16"),
        (np.full((112, 92), np.nan, np.float32), "NaN"),
    ],
)
def test_bad_images_fail_with_a_reason(template, image, reason):
    result = fit_face(template.fit, image)
    assert not result and reason in result.reason


def test_no_face_found_is_a_failure(template):
    noise = np.random.default_rng(0).uniform(0, 255, (112, 92)).astype(np.float32)
    fake = FitTemplate.build(template.fit.model, template.fit.image, template.fit.params)
    from uma.fit.fit import DetectorCalibration

    result = fit_face(fake, noise, calibration=DetectorCalibration(0.0, 0.0, 0.7))
    assert not result and ("no face" in result.reason)


def test_face_outside_the_search_box_is_a_failure(template, cases):
    case = cases[0]
    start = template.fit.params.copy()
    start[0] += 0.6 * template.fit.face_width_px  # the box ends far from the face
    box = search_box(start, template.fit.face_width_px, shift=0.05)
    result = fit_face(
        template.fit, case.image.astype(np.float32), method="saabs", start=start, box=box, rng=0
    )
    assert not result
    assert "outside the search box" in result.reason or "no face matched" in result.reason


def test_mde_of_a_shift(template):
    model, params = template.fit.model, template.fit.params
    moved = params.copy()
    moved[0] += 3.0
    moved[1] += 4.0
    assert mde_px(model, params, params) == 0.0
    assert mde_px(model, moved, params) == pytest.approx(5.0)
