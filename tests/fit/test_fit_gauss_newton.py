"""Gauss-Newton: its normal equations are the linearised cost's, and it converges near the pose."""

import numpy as np

from uma.fit import GaussNewtonConfig, gauss_newton, mde_px, search_box
from uma.fit.gauss_newton import _Problem


def test_normal_equations_are_the_linearised_cost(template, cases):
    from uma.fit.kernels import sample_at

    fit = template.fit
    image = cases[0].image.astype(np.float32)
    problem = _Problem(fit, image, GaussNewtonConfig(blur_sigma_px=1.0))
    params = cases[0].truth.copy()
    state = problem.with_prior(problem.state(params))
    n = params.size
    hessian, gradient = problem.normal_equations(state, n)
    # The same Jacobian in numpy: image gradient at the warped pixels times dW/dp.
    h = np.maximum(1e-4, 1e-3 * np.abs(params))
    shifted = np.repeat(params[None], n, axis=0) + np.diag(h)
    d_points = (problem.project(shifted).astype(np.float64) - state.points) / h[:, None, None]
    d_warp = np.einsum("kc,pkcd->pkd", problem.bary, d_points[:, problem.corners])
    gx = sample_at(problem.grad_x, problem.corners, problem.bary, state.points)[0]
    gy = sample_at(problem.grad_y, problem.corners, problem.bary, state.points)[0]
    jac = (state.gain * (gx * d_warp[..., 0] + gy * d_warp[..., 1])).T[state.visible]
    count = jac.shape[0]
    # The error is a mean over the pixels plus the prior on the action units.
    prior = np.r_[np.zeros(6), np.full(n - 6, problem.prior)]
    expected = jac.T @ jac / count + np.diag(prior)
    assert problem.prior > 0
    assert np.allclose(hessian, expected, rtol=1e-3, atol=1e-6 * np.abs(hessian).max())
    expected = jac.T @ state.residual[state.visible] / count + prior * params
    assert np.allclose(gradient, expected, rtol=1e-3, atol=1e-6)

    # And that Jacobian points where the warped image really changes (central differences).
    def warped(p):
        points = problem.project(p[None])
        return state.gain * sample_at(problem.image, problem.corners, problem.bary, points)[0]

    for k, step in ((0, 0.05), (4, 1e-3), (6, 1e-2)):
        delta = np.zeros(n)
        delta[k] = step
        column = ((warped(params + delta) - warped(params - delta)) / (2 * step))[state.visible]
        cosine = column @ jac[:, k] / np.linalg.norm(column) / np.linalg.norm(jac[:, k])
        assert cosine > 0.9


def test_pose_first_and_the_prior_keep_many_units_from_bending_onto_noise(template, cases):
    """A model whose action units can mimic a shift: fitted all at once from a shifted start,
    they bend the mesh; pose first and the prior keep them near zero."""
    import dataclasses

    from uma.fit.cost import FitTemplate

    model = template.fit.model
    # Units that move every vertex like a translation (x, y) and a scaling.
    extra = np.stack(
        [
            np.broadcast_to([0.1, 0.0, 0.0], model.vertices.shape),
            np.broadcast_to([0.0, 0.1, 0.0], model.vertices.shape),
            0.05 * model.vertices,
        ]
    )
    units = np.concatenate([model.action_units, extra])
    names = (*model.action_unit_names, "slide_x", "slide_y", "grow")
    big = dataclasses.replace(model, action_units=units, action_unit_names=names)
    params = np.r_[template.fit.params, np.zeros(3)]
    fit = FitTemplate.build(big, template.fit.image, params)
    truth = np.r_[cases[0].truth, np.zeros(3)]
    start = params.copy()
    box = search_box(start, fit.face_width_px)
    image = cases[0].image.astype(np.float32)
    careful = gauss_newton(fit, image, start, box)
    naive = gauss_newton(
        fit, image, start, box, config=GaussNewtonConfig(pose_first=False, action_prior=0.0)
    )
    assert np.abs(naive.params[-3:]).max() > 0.5  # the units did the pose's work
    assert np.abs(careful.params[-3:]).max() < 0.1
    assert mde_px(big, careful.params, truth) < 0.5


def test_gauss_newton_converges_from_nearby(template, cases):
    model = template.fit.model
    for case in cases:
        start = case.truth.copy()
        start[:2] += (1.5, -1.0)
        start[4] += 0.03
        box = search_box(template.fit.params, template.fit.face_width_px)
        result = gauss_newton(template.fit, case.image.astype(np.float32), start, box)
        assert mde_px(model, result.params, case.truth) < 0.5 < mde_px(model, start, case.truth)
        assert 0 < result.evaluations <= 200 and np.isfinite(result.cost)


def test_the_template_view_kept_between_fits_fits_as_a_fresh_one(template, cases):
    """The pixels Gauss-Newton reads are built once per template and thinning step and kept
    (session mbc12): each fit with the kept view gives what a fresh template's gives, to the bit,
    and the view holds what thinning the template gives."""
    from uma.fit.cost import FitTemplate
    from uma.fit.gauss_newton import _TemplateView

    kept = template.fit
    configs = (GaussNewtonConfig(), GaussNewtonConfig(max_pixels=300, patch_photometry=True))
    for case in cases:
        image = case.image.astype(np.float32)
        start = case.truth.copy()
        start[:2] += (1.0, 0.5)
        box = search_box(kept.params, kept.face_width_px)
        for config in configs:
            fresh = FitTemplate(kept.model, kept.params, kept.image, kept.raster, kept.values)
            want = gauss_newton(fresh, image, start, box, config=config, history=True)
            got = gauss_newton(kept, image, start, box, config=config, history=True)
            assert np.array_equal(got.params, want.params) and got.history == want.history
            assert (got.cost, got.evaluations) == (want.cost, want.evaluations)
    step = -(-kept.raster.size // 300)
    assert step > 1
    thinned, view = kept.subsampled(step), _TemplateView.of(kept, step)
    assert view is _TemplateView.of(kept, step)
    assert np.array_equal(view.tri, thinned.raster.tri) and view.tri.dtype == np.int64
    assert np.array_equal(view.corners, thinned.raster.corners)
    assert np.array_equal(view.bary, thinned.raster.bary)
    assert np.array_equal(view.values, thinned.values.astype(np.float64))
