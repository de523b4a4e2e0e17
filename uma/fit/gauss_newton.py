"""Gauss-Newton analysis-by-synthesis: the analytical baseline, and the tracker's step.

Units: parameters as in `uma.face.geometry`; intensities in grey levels.

Linearise the warp: each template pixel x_k lands at W(x_k; p) (barycentric in the projected
vertices), so r_k(p) = g * I(W(x_k; p)) + o - T(x_k) with the image gain g and offset o solved
in closed form each iteration (the photometric part, so light changes do not pull the pose).
The Jacobian is the image gradient at W times dW/dp, where dW/dp comes from finite
differences of the projected vertices (cheap: N vertices, not K pixels). The update solves
(J^T J + lambda diag(J^T J)) dp = -J^T r (Levenberg-Marquardt damping: lambda shrinks after a
step that lowers the error and grows after one that does not). Only pixels of triangles facing
the camera count. Each evaluation of the residual is one cost evaluation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.face.geometry import project
from uma.fit.cost import FitTemplate, batch_visible
from uma.fit.kernels import sample_at
from uma.fit.saabs import FitResult
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


def _patch_photometry(samples, template, tri, visible, gain, offset, n_tri):
    """Per-triangle least-squares gain and offset; small or flat patches keep the global ones."""
    keep = visible
    idx = tri[keep]
    s, t = samples[keep], template[keep]
    n = np.bincount(idx, minlength=n_tri).astype(np.float64)
    ss = np.bincount(idx, s, n_tri)
    st = np.bincount(idx, t, n_tri)
    sss = np.bincount(idx, s * s, n_tri)
    sst = np.bincount(idx, s * t, n_tri)
    with np.errstate(invalid="ignore", divide="ignore"):
        var = sss - ss * ss / n
        cov = sst - ss * st / n
        patch_gain = cov / var
        usable = (
            (n >= 8) & (var > 1e-3 * np.maximum(n, 1)) & (patch_gain > 0.2) & (patch_gain < 5.0)
        )
        patch_offset = (st - patch_gain * ss) / n
    g = np.where(usable[tri], patch_gain[tri], gain)
    o = np.where(usable[tri], patch_offset[tri], offset)
    return g, o


class _Images:
    def __init__(self, image: np.ndarray, sigma: float):
        import cv2

        smooth = np.ascontiguousarray(image, dtype=np.float32)
        if sigma > 0:
            smooth = cv2.GaussianBlur(smooth, (0, 0), sigma)
        self.image = smooth
        self.gx = np.ascontiguousarray(cv2.Sobel(smooth, cv2.CV_32F, 1, 0, ksize=3) / 8.0)
        self.gy = np.ascontiguousarray(cv2.Sobel(smooth, cv2.CV_32F, 0, 1, ksize=3) / 8.0)


def _warp_matrix(template: FitTemplate):
    """The sparse (K, N) matrix of barycentric weights: pixel positions = W @ vertex positions."""
    from scipy.sparse import csr_matrix

    r = template.raster
    rows = np.repeat(np.arange(r.size), 3)
    return csr_matrix(
        (r.bary.ravel().astype(np.float64), (rows, r.corners.ravel())),
        shape=(r.size, template.model.n_vertices),
    )


def gauss_newton(
    template: FitTemplate,
    image: np.ndarray,
    start: np.ndarray,
    box: SearchBox,
    *,
    config: GaussNewtonConfig = GaussNewtonConfig(),
) -> FitResult:
    """Fit by damped Gauss-Newton from `start`, staying inside `box`."""
    model = template.model
    step = -(-template.raster.size // max(config.max_pixels, 1))
    template = template.subsampled(step)
    images = _Images(image, config.blur_sigma_px)
    t_values = template.values.astype(np.float64)
    r = template.raster
    corners = np.ascontiguousarray(r.corners, dtype=np.int64)
    bary = np.ascontiguousarray(r.bary, dtype=np.float32)
    n_params = start.size if config.fit_actions else 6
    params = box.clip(np.asarray(start, dtype=np.float64))
    n_tri = len(model.triangles)
    warp = _warp_matrix(template)
    evaluations = 0

    def residual(p: np.ndarray):
        nonlocal evaluations
        evaluations += 1
        points = project(model, p)[None].astype(np.float32)
        samples = sample_at(images.image, corners, bary, points)[0].astype(np.float64)
        visible = batch_visible(model, points)[0][r.tri]
        s, t = samples[visible], t_values[visible]
        if s.size < 16 or s.std() < 1e-6:
            return None
        gain = np.full(samples.shape, np.cov(s, t, bias=True)[0, 1] / s.var())
        offset = np.full(samples.shape, t.mean() - gain[0] * s.mean())
        if config.patch_photometry:
            gain, offset = _patch_photometry(samples, t_values, r.tri, visible, gain, offset, n_tri)
        return gain * samples + offset - t_values, visible, gain, points[0]

    state = residual(params)
    if state is None:
        return FitResult(params=params, cost=float("inf"), evaluations=evaluations, iterations=0)
    res, visible, gain, points = state
    error = float(np.mean(res[visible] ** 2))
    damping = config.damping
    history = [error]
    iteration = 0
    for iteration in range(1, config.iterations + 1):  # noqa: B007 - reported after the loop
        # dW/dp by forward differences of the projected vertices.
        steps = np.maximum(1e-4, 1e-3 * np.abs(params[:n_params]))
        shifted = np.repeat(params[None], n_params, axis=0)
        shifted[np.arange(n_params), np.arange(n_params)] += steps
        d_points = (project(model, shifted) - points[None]) / steps[:, None, None]  # (P, N, 2)
        n_vertices = d_points.shape[1]
        flat = d_points.transpose(1, 0, 2).reshape(n_vertices, 2 * n_params)
        d_warp = (warp @ flat).reshape(-1, n_params, 2).transpose(1, 0, 2)  # (P, K, 2)
        gx = sample_at(images.gx, corners, bary, points[None].astype(np.float32))[0]
        gy = sample_at(images.gy, corners, bary, points[None].astype(np.float32))[0]
        jac = gain[None] * (gx[None] * d_warp[..., 0] + gy[None] * d_warp[..., 1])  # (P, K)
        jac = jac[:, visible].T
        hessian = jac.T @ jac
        gradient = jac.T @ res[visible]
        improved = False
        for _ in range(6):
            lhs = hessian + damping * np.diag(np.diag(hessian) + 1e-9)
            try:
                delta = -np.linalg.solve(lhs, gradient)
            except np.linalg.LinAlgError:
                damping *= 10
                continue
            candidate = params.copy()
            candidate[:n_params] += delta
            candidate = box.clip(candidate)
            trial = residual(candidate)
            if trial is not None:
                trial_error = float(np.mean(trial[0][trial[1]] ** 2))
                if trial_error < error:
                    move = np.abs(project(model, candidate) - points).max()
                    params, (res, visible, gain, points), error = candidate, trial, trial_error
                    damping = max(damping / 3, 1e-7)
                    improved = True
                    break
            damping *= 10
        history.append(error)
        if not improved or move < config.tolerance_px:
            break
    score = 1.0 - np.corrcoef(res[visible] + t_values[visible], t_values[visible])[0, 1]
    return FitResult(
        params=params,
        cost=float(score),
        evaluations=evaluations,
        iterations=iteration,
        history=tuple(history),
    )
