"""The tracker's exact cuts: the Jacobian on the visible rows only, the gate's residual reused by
`accept`, the tracker's fits left unscored. Each is checked against the computation it replaced
(kept here as the reference): every tracked value is the same to the bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from uma.mbc.encoder import FaceTracker


def _old_normal_equations(self, state, n_params: int):
    """The Jacobian of every template pixel, then the visible rows (as before the cut)."""
    from uma.face.geometry import N_POSE
    from uma.fit.kernels import warp_jacobian

    p = state.params
    h = np.maximum(1e-4, 1e-3 * np.abs(p[:n_params]))
    shifted = np.repeat(p[None], n_params, axis=0)
    shifted[np.arange(n_params), np.arange(n_params)] += h
    d_points = (self.project(shifted).astype(np.float64) - state.points) / h[:, None, None]
    every = np.arange(self.corners.shape[0])
    jac = warp_jacobian(
        self.grad_x, self.grad_y, self.corners, self.bary, state.points, d_points, state.gain,
        every,
    )[state.visible]  # fmt: skip
    count = jac.shape[0]
    hessian = jac.T @ jac / count
    gradient = jac.T @ state.residual[state.visible] / count
    units = np.arange(N_POSE, n_params)
    hessian[units, units] += self.prior
    gradient[N_POSE:n_params] += self.prior * p[N_POSE:n_params]
    return hessian, gradient


def _old_accept(self, image, params) -> None:
    """`AppearanceGate.accept` computing its own residual (as before the cut)."""
    samples, visible = self._samples(image, params, reuse=True)
    self._cached = None
    self.frames += 1
    if self.mean is None:
        self.mean = np.where(visible, samples, np.nan)
        self.scale = 0.0
        return
    known = visible & np.isfinite(self.mean)
    fresh = visible & ~known
    self.mean[fresh] = samples[fresh]
    residual = self._residual(samples, known) if known.sum() >= 16 else None
    if residual is None:
        return
    size = 1.4826 * float(np.median(np.abs(residual)))
    self.scale = size if self.scale == 0.0 else (1 - self.rate) * self.scale + self.rate * size
    departing = np.abs(residual) > self.outlier_k * max(self.scale, 2.0)
    rate = np.where(departing, 0.1 * self.rate, self.rate)
    target = self.mean[known] + residual
    self.mean[known] += rate * (target - self.mean[known])


def _tracked(description, pictures) -> list[np.ndarray]:
    """Per picture: the parameters, score, evaluations and success, and the gate's state."""
    tracker = FaceTracker(description, rng=0)
    out = []
    for index, picture in enumerate(pictures):
        r = tracker.track(picture, frame=index)
        gate = tracker.gate
        out.append(
            np.r_[
                getattr(r, "params", np.zeros(0)),
                getattr(r, "score", np.nan),
                getattr(r, "evaluations", -1),
                float(bool(r)),
                gate.scale,
                gate.frames,
                [] if gate.mean is None else gate.mean,
            ]
        )
    return out


def _before_and_after(monkeypatch, description, pictures):
    import uma.mbc.encoder as encoder
    from uma.fit.gauss_newton import _Problem, gauss_newton
    from uma.mbc.tracking_gate import AppearanceGate

    after = _tracked(description, pictures)
    with monkeypatch.context() as patch:
        patch.setattr(_Problem, "normal_equations", _old_normal_equations)
        patch.setattr(AppearanceGate, "accept", _old_accept)
        patch.setattr(
            encoder, "gauss_newton", lambda *a, **k: gauss_newton(*a, **{**k, "scored": True})
        )
        before = _tracked(description, pictures)
    return before, after


def test_the_exact_cuts_track_the_talking_head_to_the_bit(monkeypatch, head, head_frames):
    before, after = _before_and_after(monkeypatch, head.description, head_frames)
    assert len(before) == len(head_frames)
    for old, new in zip(before, after, strict=True):
        assert np.array_equal(old, new, equal_nan=True)


def test_the_exact_cuts_track_akiyo_to_the_bit(monkeypatch):
    from uma.bench.mbc_clips import file_clip
    from uma.face.clip import load_points
    from uma.mbc.profile import describe_clip_with_ring
    from uma.paths import codecs_dir

    points = load_points(codecs_dir() / "face" / "akiyo.yaml")
    if points.video is None or not Path(points.video).is_file():
        pytest.skip("akiyo's video is not here (../shared)")
    clip = file_clip(Path(points.video), describe_clip_with_ring(points, seed=0), 24)
    height = clip.frames[0].shape[0] * 2 // 3
    before, after = _before_and_after(
        monkeypatch, clip.description, [f[:height] for f in clip.frames]
    )
    for old, new in zip(before, after, strict=True):
        assert np.array_equal(old, new, equal_nan=True)


def test_the_visible_rows_are_the_whole_jacobian_s(head, head_frames):
    """The kernel's rows for some pixels equal those pixels' rows of the whole Jacobian."""
    from uma.fit.gauss_newton import GaussNewtonConfig, _Problem
    from uma.fit.kernels import warp_jacobian

    problem = _Problem(
        FaceTracker(head.description).template, head_frames[1].astype(np.float32),
        GaussNewtonConfig(),
    )  # fmt: skip
    turned = head.params_at(1).copy()
    turned[4] += 0.8  # yawed: some triangles face away
    state = problem.state(turned)
    count = problem.corners.shape[0]
    d_points = np.random.default_rng(0).normal(size=(4,) + state.points.shape[1:])
    rows = np.flatnonzero(state.visible)
    assert 0 < rows.size < count
    args = (problem.grad_x, problem.grad_y, problem.corners, problem.bary, state.points)
    every = warp_jacobian(*args, d_points, state.gain, np.arange(count))
    some = warp_jacobian(*args, d_points, state.gain, rows)
    assert some.shape == (rows.size, 4) and np.array_equal(some, every[rows])
