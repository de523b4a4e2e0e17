"""Gauss-Newton analysis-by-synthesis: the analytical baseline, and the tracker's step.

Units: parameters as in `uma.face.geometry`; intensities in grey levels.

Linearise the warp: each template pixel x_k lands at W(x_k; p) (barycentric in the projected
vertices), so r_k(p) = g * I(W(x_k; p)) + o - T(x_k), with the image gain g and offset o solved
in closed form at each evaluation (the photometric part, so a change of light does not pull the
pose); with `patch_photometry` a gain and offset per triangle patch, the counterpart of SAABs'
illumination compensation. The Jacobian is the image gradient at W times dW/dp, where dW/dp is
barycentric in the derivatives of the projected vertices (forward differences: N vertices, not
K pixels); a compiled kernel builds J and BLAS forms J^T J and J^T r. The update solves
(J^T J + lambda diag(J^T J)) dp = -J^T r (Levenberg-Marquardt damping: lambda shrinks after a
step that lowers the error and grows after one that does not). Only pixels of triangles facing
the camera count. Each evaluation of the residual is one cost evaluation. By default the pose
converges first and the action units join afterwards, under a weak Gaussian prior.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.face.geometry import N_POSE
from uma.fit.cost import FitTemplate, batch_visible, blurred
from uma.fit.result import FitResult
from uma.fit.search import SearchBox

__all__ = ["GaussNewtonConfig", "gauss_newton"]


@dataclass(frozen=True)
class GaussNewtonConfig:
    iterations: int = 30
    damping: float = 1e-3
    blur_sigma_px: float = 0.5  # smooths the image so its gradient reaches a little further
    tolerance_px: float = 1e-3  # stop when the largest vertex move is below this
    fit_actions: bool = True
    max_pixels: int = 8000  # every n-th template pixel beyond this many (a CIF face has ~19,000)
    # A gain and offset per triangle patch instead of one for the image: follows light that
    # changes across the face (the counterpart of SAABs' illumination compensation).
    patch_photometry: bool = False
    pose_first: bool = True  # converge on the pose, then add the action units
    # A Gaussian prior on the action units, scaled by how well the pose alone explains the image:
    # the error adds action_prior * e0 * sum(a^2), with e0 the mean squared residual when the
    # units join (a unit of 1 costs action_prior times the residual left then). Models with
    # many units otherwise bend onto noise: on Candide-3 (65 units) 20-30 px without it and
    # pose_first, 0.3-0.5 px with both; the hybrid 5-11 px without it, 0.4-0.5 px with it. It
    # costs precision where the units move a lot: the CIF talking head's median 0.08 -> 0.19 px.
    action_prior: float = 0.1

    def __post_init__(self) -> None:
        if self.action_prior < 0:
            raise ValueError(f"Gauss-Newton: action_prior >= 0 expected, got {self.action_prior}")
        if self.iterations < 1 or self.max_pixels < 16:
            raise ValueError(
                f"Gauss-Newton: iterations >= 1 and max_pixels >= 16 expected, got "
                f"{self.iterations} and {self.max_pixels}"
            )
        if not (self.damping > 0 and self.blur_sigma_px >= 0 and self.tolerance_px >= 0):
            raise ValueError("Gauss-Newton: damping > 0, blur and tolerance >= 0 expected")


@dataclass(frozen=True, eq=False)
class _State:
    params: np.ndarray
    points: np.ndarray  # (1, N, 2) float32
    residual: np.ndarray  # (K,)
    visible: np.ndarray  # (K,) bool
    gain: np.ndarray  # (K,)
    error: float


@dataclass(frozen=True, eq=False)
class _TemplateView:
    """A template's pixels as the fit's kernels read them (every `step`-th one): the same on
    every frame, so built once per template and step and kept on it (never written to)."""

    tri: np.ndarray  # (K,) int64
    corners: np.ndarray  # (K, 3) int64
    bary: np.ndarray  # (K, 3) float32
    values: np.ndarray  # (K,) float64
    vertices: np.ndarray  # (N, 3) float64
    units: np.ndarray  # (A, N, 3) float64

    @classmethod
    def of(cls, template: FitTemplate, step: int) -> _TemplateView:
        cache = template.__dict__.setdefault("_gauss_newton_views", {})
        if step not in cache:
            thinned = template.subsampled(step)
            model, r = thinned.model, thinned.raster
            units = model.action_units if model.n_actions else np.zeros((0,) + model.vertices.shape)
            cache[step] = cls(
                tri=np.ascontiguousarray(r.tri, dtype=np.int64),
                corners=np.ascontiguousarray(r.corners, dtype=np.int64),
                bary=np.ascontiguousarray(r.bary, dtype=np.float32),
                values=thinned.values.astype(np.float64),
                vertices=np.ascontiguousarray(model.vertices, dtype=np.float64),
                units=np.ascontiguousarray(units, dtype=np.float64),
            )
        return cache[step]


class _Problem:
    """The residual and normal equations of one fit, with everything precomputed."""

    def __init__(self, template: FitTemplate, image: np.ndarray, config: GaussNewtonConfig):
        import cv2

        step = -(-template.raster.size // max(config.max_pixels, 1))
        smooth = blurred(image, config.blur_sigma_px)
        self.image = smooth
        self.grad_x = np.ascontiguousarray(cv2.Sobel(smooth, cv2.CV_32F, 1, 0, ksize=3) / 8.0)
        self.grad_y = np.ascontiguousarray(cv2.Sobel(smooth, cv2.CV_32F, 0, 1, ksize=3) / 8.0)
        model = template.model
        self.model = model
        self.config = config
        view = _TemplateView.of(template, step)
        self.tri, self.corners, self.bary = view.tri, view.corners, view.bary
        self.n_tri = len(model.triangles)
        self.values, self.vertices, self.units = view.values, view.vertices, view.units
        self.prior = 0.0  # set when the action units join (`with_prior`)
        self.evaluations = 0

    def with_prior(self, state: _State) -> _State:
        """`state` re-scored with the prior scaled by its own residual (one evaluation)."""
        residual = state.residual[state.visible]
        self.prior = self.config.action_prior * float(np.mean(residual**2))
        return self.state(state.params) or state

    def project(self, params: np.ndarray) -> np.ndarray:
        from uma.fit.kernels import project_batch

        return project_batch(self.vertices, self.units, np.ascontiguousarray(params))

    def state(self, params: np.ndarray) -> _State | None:
        from uma.fit.kernels import sample_at
        from uma.fit.photometry import photometric_residual

        self.evaluations += 1
        points = self.project(params[None])
        samples = sample_at(self.image, self.corners, self.bary, points)[0].astype(np.float64)
        visible = batch_visible(self.model, points)[0][self.tri]
        ok, residual, gain, error = photometric_residual(
            samples, self.values, self.tri, visible, self.n_tri, self.config.patch_photometry
        )
        if not ok:
            return None
        actions = params[N_POSE:]
        error = float(error + self.prior * np.sum(actions**2))
        if not np.isfinite(error):
            return None
        return _State(params, points, residual, visible, gain, error)

    def normal_equations(self, state: _State, n_params: int):
        """J^T J (P, P) and J^T r (P,) over the visible pixels."""
        from uma.fit.kernels import warp_jacobian

        p = state.params
        h = np.maximum(1e-4, 1e-3 * np.abs(p[:n_params]))
        shifted = np.repeat(p[None], n_params, axis=0)
        shifted[np.arange(n_params), np.arange(n_params)] += h
        d_points = (self.project(shifted).astype(np.float64) - state.points) / h[:, None, None]
        rows = np.flatnonzero(state.visible)
        jac = warp_jacobian(
            self.grad_x, self.grad_y, self.corners, self.bary, state.points, d_points, state.gain,
            rows,
        )  # fmt: skip
        count = jac.shape[0]
        hessian = jac.T @ jac / count
        gradient = jac.T @ state.residual[state.visible] / count
        # The prior's part (per pixel, as the error is a mean).
        units = np.arange(N_POSE, n_params)
        hessian[units, units] += self.prior
        gradient[N_POSE:n_params] += self.prior * p[N_POSE:n_params]
        return hessian, gradient


def _iterate(problem, state, box, n_params, iterations, trace):
    """Levenberg-Marquardt steps on the first `n_params` parameters until they stop moving."""
    config = problem.config
    damping = config.damping
    iteration = 0
    for iteration in range(1, iterations + 1):  # noqa: B007 - reported after the loop
        hessian, gradient = problem.normal_equations(state, n_params)
        improved, move = False, 0.0
        for _ in range(6):
            lhs = hessian + damping * np.diag(np.diag(hessian) + 1e-9)
            try:
                delta = -np.linalg.solve(lhs, gradient)
            except np.linalg.LinAlgError:
                damping *= 10
                continue
            candidate = state.params.copy()
            candidate[:n_params] += delta
            candidate = box.clip(candidate)
            trial = problem.state(candidate) if np.all(np.isfinite(candidate)) else None
            if trial is not None and trial.error < state.error:
                move = float(np.abs(trial.points - state.points).max())
                state = trial
                damping = max(damping / 3, 1e-7)
                improved = True
                break
            damping *= 10
        trace.append(state.error)
        if not improved or move < config.tolerance_px:
            break
    return state, iteration


def gauss_newton(
    template: FitTemplate,
    image: np.ndarray,
    start: np.ndarray,
    box: SearchBox,
    *,
    config: GaussNewtonConfig = GaussNewtonConfig(),
    history: bool = False,
    scored: bool = True,
) -> FitResult:
    """Fit by damped Gauss-Newton from `start`, staying inside `box`. A start where nothing
    can be compared (flat image, face off the picture) returns the start with infinite cost.
    `scored=False` leaves the final cost out (NaN; the fit is the same): for a caller that
    scores the parameters its own way."""
    problem = _Problem(template, image, config)
    params = box.clip(np.asarray(start, dtype=np.float64))
    n_params = params.size if config.fit_actions else N_POSE
    state = problem.state(params)
    if state is None:
        return FitResult(params=params, cost=float("inf"), evaluations=1, iterations=0)
    trace = [state.error]
    used = 0
    if config.pose_first and n_params > N_POSE:
        # The pose alone first: from afar, the action units would bend the mesh onto the texture
        # instead of moving it (with Candide-3's 65 units, errors of 20 px instead of 0.1).
        state, used = _iterate(problem, state, box, N_POSE, config.iterations, trace)
    if n_params > N_POSE and config.action_prior > 0:
        state = problem.with_prior(state)
    state, more = _iterate(problem, state, box, n_params, max(config.iterations - used, 1), trace)
    iteration = used + more
    cost = float("nan")
    if scored:
        v = state.visible
        fitted = state.residual[v] + problem.values[v]
        score = float(np.corrcoef(fitted, problem.values[v])[0, 1])
        cost = 1.0 - score if np.isfinite(score) else float("inf")
    return FitResult(
        params=state.params,
        cost=cost,
        evaluations=problem.evaluations,
        iterations=iteration,
        history=tuple(trace) if history else (),
    )
