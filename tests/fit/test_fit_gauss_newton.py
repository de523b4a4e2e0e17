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
    state = problem.state(params)
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
    assert np.allclose(hessian, jac.T @ jac, rtol=1e-3, atol=1e-6 * np.abs(hessian).max())
    assert np.allclose(gradient, jac.T @ state.residual[state.visible], rtol=1e-3, atol=1e-3)

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
