"""Mean distance error (MDE): root mean square distance per model point, in pixels."""

from __future__ import annotations

import numpy as np

from uma.face.geometry import project
from uma.face.model import FaceModel

__all__ = ["mde_px"]


def mde_px(model: FaceModel, fitted: np.ndarray, truth: np.ndarray) -> float:
    """RMS over all model vertices of the distance between their fitted and true projections."""
    difference = project(model, fitted) - project(model, truth)
    return float(np.sqrt(np.mean(np.sum(difference**2, axis=-1))))
