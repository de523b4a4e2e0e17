"""SAABs' perturbation functions: random steps measured in pixels of model-point motion.

Units: a step is the root mean square distance the model's projected vertices move, in pixels;
parameters as in `uma.face.geometry`. The parameters act on the image at very different rates
(a pixel of tx moves every point by a pixel, a radian of yaw by half the face width, an action
unit by a few pixels near the mouth only) and some act together (yaw and tx both slide the face
sideways). "metric" draws steps from a Gaussian whitened by the local metric of the projection,
M = J^T J / N with J the Jacobian of the projected vertices: every direction in parameter space
then moves the points equally far, and correlated parameters are decorrelated. "axes" scales
each parameter by its own rate only (no decorrelation), as a simpler baseline.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.face.geometry import project
from uma.face.model import FaceModel

__all__ = ["PERTURBATIONS", "point_metric", "Perturbation"]

PERTURBATIONS = ("metric", "axes")
_RIDGE = 1e-3  # keeps the metric invertible when parameters move the points alike


def point_metric(model: FaceModel, params: np.ndarray, active: np.ndarray) -> np.ndarray:
    """Mean squared vertex motion (px^2) per unit^2 of the active parameters: (n, n)."""
    params = np.asarray(params, dtype=np.float64)
    index = np.flatnonzero(active)
    h = np.maximum(1e-6, 1e-5 * np.abs(params[index]))
    shifted = np.repeat(params[None], index.size + 1, axis=0)
    shifted[np.arange(1, index.size + 1), index] += h
    points = project(model, shifted)
    jac = ((points[1:] - points[0]) / h[:, None, None]).reshape(index.size, -1)  # (n, 2N)
    metric = jac @ jac.T / points.shape[1]
    # Relative to each parameter's own rate (units differ); the floor covers a parameter that
    # moves no point at all.
    diagonal = np.maximum(np.diag(metric), 1e-12 * max(float(np.max(np.diag(metric))), 1e-12))
    return metric + _RIDGE * np.diag(diagonal)


@dataclass(frozen=True, eq=False)
class Perturbation:
    """Random steps of the `active` parameters whose points move `step_px` RMS on average."""

    active: np.ndarray  # (P,) bool
    factor: np.ndarray  # (n, n): step = z @ factor.T for one pixel of RMS motion

    @classmethod
    def build(
        cls, model: FaceModel, params: np.ndarray, active: np.ndarray, *, kind: str = "metric"
    ) -> Perturbation:
        if kind not in PERTURBATIONS:
            raise ValueError(f"perturbation: expected one of {PERTURBATIONS}, got {kind!r}")
        metric = point_metric(model, params, active)
        n = metric.shape[0]
        if kind == "axes":
            factor = np.diag(1.0 / np.sqrt(np.diag(metric)))
        else:
            # Sampling with the inverse Cholesky factor gives steps of covariance M^-1.
            factor = np.linalg.inv(np.linalg.cholesky(metric)).T
        return cls(active=np.asarray(active, dtype=bool), factor=factor / np.sqrt(n))

    def __call__(
        self, rng: np.random.Generator, current: np.ndarray, tries: int, step_px: float
    ) -> np.ndarray:
        """`tries` proposals around `current` (tries, P)."""
        z = rng.standard_normal((tries, self.factor.shape[0]))
        out = np.repeat(current[None], tries, axis=0)
        out[:, self._columns] += step_px * (z @ self.factor.T)
        return out

    @property
    def _columns(self):
        """The active parameters as a slice when they are one run (cheaper than a mask)."""
        columns = self.__dict__.get("_columns_cache")
        if columns is None:
            index = np.flatnonzero(self.active)
            contiguous = index.size and index[-1] - index[0] + 1 == index.size
            columns = slice(int(index[0]), int(index[-1]) + 1) if contiguous else self.active
            object.__setattr__(self, "_columns_cache", columns)
        return columns
