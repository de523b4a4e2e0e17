"""Fit the wireframe to clicked feature points: shape units, pose and expression by least squares.

Units: pixels for points and translations, radians for rotations, unitless coefficients.

This is the offline "manual fitting" of the pseudo-automatic scheme: a person clicks MPEG-4
feature points on a frontal template image, and the model's shape units (the person's
proportions), pose and action units are chosen so the model's points project onto the clicks.
Coefficients carry a light ridge penalty, so points that say nothing about a unit leave it at 0.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from uma.face.geometry import N_POSE, rotation_matrix
from uma.face.model import FaceModel
from uma.failure import Failure

__all__ = ["PointFit", "fit_points", "check_points", "MIN_POINTS", "REQUIRED_REGIONS"]

MIN_POINTS = 6
# A fit needs a point on each eye and one on the mouth or chin: without them the scale, roll and
# the face's vertical extent are guesses. MPEG-4 numbers the subject's left side odd.
REQUIRED_REGIONS = {
    "left eye": ("3.1", "3.3", "3.5", "3.7", "3.9", "3.11"),
    "right eye": ("3.2", "3.4", "3.6", "3.8", "3.10", "3.12"),
    "mouth or chin": ("8.1", "8.2", "8.3", "8.4", "2.1", "2.2", "2.3", "2.4", "2.5", "2.10"),
}
# Ridge weight on shape and action coefficients, in pixels of residual per unit coefficient
# per 100 px of face scale: small enough to fit clean clicks to well under 0.1 px.
RIDGE_PX = 0.02


@dataclass(frozen=True, eq=False)
class PointFit:
    """A successful fit: shape (S,), params (6 + A,), and how well the points agree."""

    shape: np.ndarray
    params: np.ndarray
    names: tuple[str, ...]
    residuals_px: np.ndarray  # (M, 2)

    @property
    def rms_px(self) -> float:
        return float(np.sqrt(np.mean(np.sum(self.residuals_px**2, axis=1))))

    def __bool__(self) -> bool:
        return True


def check_points(
    model: FaceModel, points: Mapping[str, tuple[float, float]], image_shape: tuple[int, int] | None
) -> Failure | None:
    """Why `points` cannot be fitted (too few known, a region missing, outside the image,
    collinear, mirrored), or None."""
    known = [n for n in points if n in model.feature_points]
    unknown = [n for n in points if n not in model.feature_points]
    if len(known) < MIN_POINTS:
        extra = f" (not on this model: {', '.join(unknown)})" if unknown else ""
        return Failure(
            f"need at least {MIN_POINTS} feature points the model knows, got {len(known)}{extra}"
        )
    for region, names in REQUIRED_REGIONS.items():
        usable = [n for n in names if n in model.feature_points]
        if usable and not any(n in points for n in usable):
            return Failure(f"no feature point on the {region}: give one of {', '.join(usable)}")
    xy = np.array([points[n] for n in known], dtype=np.float64)
    if not np.all(np.isfinite(xy)):
        return Failure("feature points must be finite numbers")
    if image_shape is not None:
        height, width = image_shape
        outside = [
            n
            for n, (x, y) in zip(known, xy, strict=True)
            if not (0 <= x < width and 0 <= y < height)
        ]
        if outside:
            return Failure(
                f"feature point(s) {', '.join(outside)} lie outside the {width}x{height} image"
            )
    spread = np.linalg.svd(xy - xy.mean(axis=0), compute_uv=False)
    if spread[0] < 1e-9 or spread[1] / spread[0] < 0.05:
        return Failure("feature points are degenerate: they (nearly) lie on one line")
    return _mirrored(model, points)


def _mirrored(model: FaceModel, points: Mapping[str, tuple[float, float]]) -> Failure | None:
    """A Failure when left eye, right eye and mouth turn the other way round than on the model
    (a mirror image: left and right swapped); no rotation of a face does that."""
    picked = []
    for names in REQUIRED_REGIONS.values():
        usable = [n for n in names if n in model.feature_points and n in points]
        if not usable:
            return None
        picked.append(usable[0])
    image = np.array([points[n] for n in picked], dtype=np.float64)
    frontal = model.vertices[model.feature_indices(picked), :2] * np.array([1.0, -1.0])

    def turn(p: np.ndarray) -> float:
        (ux, uy), (vx, vy) = p[1] - p[0], p[2] - p[0]
        return float(ux * vy - uy * vx)

    if turn(image) * turn(frontal) < 0:
        return Failure(
            f"feature points {', '.join(picked)} are mirrored: left and right swapped? "
            "(MPEG-4 left is the subject's left, odd numbers)"
        )
    return None


def _similarity(model_xy: np.ndarray, image_xy: np.ndarray) -> tuple[float, float, float, float]:
    """Scale, roll and translation taking model (x, y up) onto image (x, y down), least squares."""
    src = model_xy * np.array([1.0, -1.0])
    src_c, dst_c = src - src.mean(axis=0), image_xy - image_xy.mean(axis=0)
    a = np.sum(src_c * dst_c)
    b = np.sum(src_c[:, 0] * dst_c[:, 1] - src_c[:, 1] * dst_c[:, 0])
    scale = np.hypot(a, b) / np.sum(src_c**2)
    angle = np.arctan2(b, a)
    # Image y points down, so a clockwise image rotation is a positive model roll.
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    t = image_xy.mean(axis=0) - scale * src.mean(axis=0) @ rot.T
    return float(scale), float(-angle), float(t[0]), float(t[1])


def fit_points(
    model: FaceModel,
    points: Mapping[str, tuple[float, float]],
    *,
    image_shape: tuple[int, int] | None = None,
    fit_shape: bool = True,
    fit_actions: bool = True,
    ridge_px: float = RIDGE_PX,
) -> PointFit | Failure:
    """Least-squares fit of shape, pose and actions to named points; a `Failure` says why not."""
    from scipy.optimize import least_squares

    problem = check_points(model, points, image_shape)
    if problem is not None:
        return problem
    names = tuple(n for n in points if n in model.feature_points)
    index = model.feature_indices(list(names))
    target = np.array([points[n] for n in names], dtype=np.float64)
    base = model.vertices[index]
    shape_units = model.shape_units[:, index] if fit_shape else model.shape_units[:0, index]
    action_units = model.action_units[:, index] if fit_actions else model.action_units[:0, index]
    n_shape, n_action = shape_units.shape[0], action_units.shape[0]

    scale0, roll0, tx0, ty0 = _similarity(base[:, :2], target)
    x0 = np.concatenate([[tx0, ty0, scale0, 0.0, 0.0, roll0], np.zeros(n_shape + n_action)])
    ridge = ridge_px * scale0 / 100.0

    def residuals(x: np.ndarray) -> np.ndarray:
        coeffs = x[N_POSE:]
        vertices = base + np.tensordot(coeffs[:n_shape], shape_units, axes=1)
        vertices = vertices + np.tensordot(coeffs[n_shape:], action_units, axes=1)
        rotated = vertices @ rotation_matrix(x[3], x[4], x[5]).T
        projected = np.column_stack([x[0] + x[2] * rotated[:, 0], x[1] - x[2] * rotated[:, 1]])
        return np.concatenate([(projected - target).ravel(), ridge * coeffs])

    lower = np.concatenate(
        [[-np.inf, -np.inf, 1e-6, -0.8, -0.8, -np.pi], np.full(n_shape + n_action, -2.0)]
    )
    upper = np.concatenate(
        [[np.inf, np.inf, np.inf, 0.8, 0.8, np.pi], np.full(n_shape + n_action, 2.0)]
    )
    x0 = np.clip(x0, lower + 1e-9, upper - 1e-9)
    solution = least_squares(
        residuals, x0, bounds=(lower, upper), x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12
    )
    if not np.all(np.isfinite(solution.x)):
        return Failure("least squares diverged")
    x = solution.x
    shape = np.zeros(model.n_shapes)
    actions = np.zeros(model.n_actions)
    if fit_shape:
        shape = x[N_POSE : N_POSE + n_shape]
    if fit_actions:
        actions = x[N_POSE + n_shape :]
    params = np.concatenate([x[:N_POSE], actions])
    residual = residuals(x)[: 2 * len(names)].reshape(-1, 2)
    return PointFit(shape=shape, params=params, names=names, residuals_px=residual)
