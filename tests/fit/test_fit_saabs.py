"""SAABs: the Metropolis rule, the schedule, the perturbation, and known poses recovered."""

import numpy as np
import pytest

from uma.face.geometry import project
from uma.fit import (
    AnnealingSchedule,
    Cost,
    Perturbation,
    SaabsConfig,
    anneal,
    mde_px,
    metropolis_accept,
    point_metric,
    saabs,
    search_box,
)
from uma.fit.saabs import Stage, stages


def test_metropolis_rule():
    assert metropolis_accept(-0.1, 0.01, 0.999)
    assert metropolis_accept(0.0, 0.0, 0.5)
    assert not metropolis_accept(0.01, 0.0, 0.0)
    assert not metropolis_accept(float("inf"), 1.0, 0.0)
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
    assert schedule.step_scale(0.1) == 1.0
    assert schedule.step_scale(0.001) == pytest.approx(0.1)
    assert schedule.step_scale(1e-9) == schedule.min_step_fraction
    for bad in (
        {"steps": 0},
        {"tries": 0},
        {"final_temperature": 1.0},
        {"initial_step": 0.0},
        {"patience": -1},
    ):
        with pytest.raises(ValueError):
            AnnealingSchedule(**bad)
    with pytest.raises(ValueError):
        SaabsConfig(perturbation="nope")
    with pytest.raises(ValueError):
        SaabsConfig(global_stages=())
    for bad in ({"blur": 1.0}, {"blur": 0.05, "band": 0.02}, {"blur": 0.0, "illumination": 2}):
        with pytest.raises(ValueError):
            Stage(**bad)


def test_stages_cool_as_the_whole_schedule():
    whole = AnnealingSchedule(steps=38, initial_temperature=0.03, final_temperature=1e-4)
    parts = stages(whole, 2)
    assert sum(p.steps for p in parts) == whole.steps
    assert parts[0].initial_temperature == pytest.approx(whole.initial_temperature)
    assert parts[-1].final_temperature == pytest.approx(whole.final_temperature)
    # The second stage starts where the first one would have gone on, with steps to match.
    t = whole.initial_temperature * whole.cooling ** parts[0].steps
    assert parts[1].initial_temperature == pytest.approx(t)
    assert parts[1].initial_step == pytest.approx(whole.initial_step * whole.step_scale(t))
    assert parts[1].cooling == pytest.approx(whole.cooling)


def test_metric_perturbation_moves_points_by_the_step(template):
    fit = template.fit
    model, params = fit.model, fit.params
    active = np.ones(params.size, dtype=bool)
    moves = Perturbation.build(model, params, active)
    proposals = moves(np.random.default_rng(0), params, 4000, 0.5)
    motion = project(model, proposals) - project(model, params)
    rms = np.sqrt(np.mean(np.sum(motion**2, axis=-1), axis=-1))
    assert np.sqrt(np.mean(rms**2)) == pytest.approx(0.5, rel=0.05)
    # Whitened: along every parameter direction the points move alike on average.
    steps = proposals - params
    metric = point_metric(model, params, active)
    whitened = np.cov(steps.T) @ metric
    assert np.allclose(np.diag(whitened), np.diag(whitened).mean(), rtol=0.15)
    pose_only = Perturbation.build(model, params, np.arange(params.size) < 6)
    assert np.all(pose_only(np.random.default_rng(1), params, 5, 1.0)[:, 6:] == params[6:])


def test_anneal_stays_in_the_box_and_counts(template):
    fit = template.fit
    box = search_box(fit.params, fit.face_width_px)
    cost = Cost(fit, fit.image)
    moves = Perturbation.build(fit.model, fit.params, np.ones(fit.params.size, bool))
    schedule = AnnealingSchedule(steps=5, tries=4, initial_step=1.0)
    out = anneal(
        cost, fit.params, box, schedule, moves, rng=np.random.default_rng(0), face_width_px=80
    )
    assert box.contains(out.params)
    assert out.evaluations == cost.evaluations == 1 + 5 * 4
    assert out.cost == pytest.approx(0.0, abs=1e-5)  # the start is perfect: it stays the best
    assert len(out.history) == 6 and list(out.history) == sorted(out.history, reverse=True)


def test_saabs_recovers_known_poses(template, cases):
    model = template.fit.model
    errors, starts = [], []
    for seed, case in enumerate(cases):
        start = template.fit.params
        box = search_box(start, template.fit.face_width_px)
        cost = Cost(template.fit, case.image.astype(np.float32))
        result = saabs(cost, start, box, rng=seed)
        assert result.evaluations <= SaabsConfig().budget
        assert np.all(np.isfinite(result.params)) and box.contains(result.params)
        errors.append(mde_px(model, result.params, case.truth))
        starts.append(mde_px(model, start, case.truth))
    assert np.median(errors) < 0.8
    assert max(errors) < 1.5 < min(starts)


def test_same_generator_same_fit(template, cases):
    case = cases[0]
    box = search_box(template.fit.params, template.fit.face_width_px)
    image = case.image.astype(np.float32)
    a = saabs(Cost(template.fit, image), template.fit.params, box, rng=7)
    b = saabs(Cost(template.fit, image), template.fit.params, box, rng=7)
    c = saabs(Cost(template.fit, image), template.fit.params, box, rng=8)
    assert np.array_equal(a.params, b.params)
    assert not np.array_equal(a.params, c.params)
