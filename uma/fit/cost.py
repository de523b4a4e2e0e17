"""The fitting cost: how well the template, warped by candidate parameters, matches an image.

Units: pixels; parameters as in `uma.face.geometry` ([tx_px, ty_px, scale_px, rx_rad, ry_rad,
rz_rad, action units...]). Cost = 1 - normalised correlation coefficient over the template's
visible pixels (0 for a perfect match, up to 2), optionally after illumination compensation
(each triangle patch normalised to zero mean and unit variance in both images). Candidates are
evaluated in batches by compiled kernels; every evaluation is counted.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.face.geometry import project, visible_triangles
from uma.face.model import FaceModel
from uma.face.render import Raster, rasterize

__all__ = ["FitTemplate", "Cost", "batch_visible"]


@dataclass(frozen=True, eq=False)
class FitTemplate:
    """A personal model placed on its template image, rasterised once for fitting."""

    model: FaceModel
    params: np.ndarray
    image: np.ndarray  # float32 gray
    raster: Raster
    values: np.ndarray  # (K,) float32 template values at the raster pixels

    @classmethod
    def build(cls, model: FaceModel, gray: np.ndarray, params: np.ndarray) -> FitTemplate:
        image = np.ascontiguousarray(gray, dtype=np.float32)
        params = np.asarray(params, dtype=np.float64)
        points = project(model, params)
        raster = rasterize(
            points, model.triangles, image.shape, triangle_mask=visible_triangles(model, params)
        )
        # Keep the pixels whose centres lie inside their triangle: at the template's own pose
        # they map exactly onto themselves, so the cost there is exactly zero.
        raster = raster.take(raster.inside)
        values = image[raster.ys, raster.xs].astype(np.float32)
        return cls(model=model, params=params, image=image, raster=raster, values=values)

    def subsampled(self, step: int) -> FitTemplate:
        """Every `step`-th template pixel: a cheaper cost for the coarse global search."""
        if step <= 1:
            return self
        keep = np.arange(0, self.raster.size, step)
        raster = self.raster.take(keep)
        return FitTemplate(self.model, self.params, self.image, raster, self.values[keep])

    @property
    def face_width_px(self) -> float:
        points = project(self.model, self.params)
        return float(np.ptp(points[:, 0]))


def batch_visible(model: FaceModel, points: np.ndarray) -> np.ndarray:
    """Front-facing triangles for projected points (B, N, 2) -> (B, T) bool."""
    tri = model.triangles
    a, b, c = points[:, tri[:, 0]], points[:, tri[:, 1]], points[:, tri[:, 2]]
    cross = (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (
        c[..., 0] - a[..., 0]
    )
    return cross < 0


class Cost:
    """1 - NCC between the template and `image` warped by each candidate; counts evaluations."""

    def __init__(self, template: FitTemplate, image: np.ndarray, *, illumination: bool = False):
        self.template = template
        self.image = np.ascontiguousarray(image, dtype=np.float32)
        self.illumination = illumination
        self.evaluations = 0
        r = template.raster
        self._corners = np.ascontiguousarray(r.corners, dtype=np.int64)
        self._bary = np.ascontiguousarray(r.bary, dtype=np.float32)
        self._tri = np.ascontiguousarray(r.tri, dtype=np.int64)
        self._values = np.ascontiguousarray(template.values, dtype=np.float32)

    def __call__(self, params: np.ndarray) -> np.ndarray:
        """Costs of candidates (B, P) -> (B,), or of one (P,) -> a 0-d array."""
        from uma.fit.kernels import ncc_scores, patch_ncc_scores

        params = np.asarray(params, dtype=np.float64)
        single = params.ndim == 1
        batch = np.atleast_2d(params)
        points = np.ascontiguousarray(project(self.template.model, batch), dtype=np.float32)
        visible = batch_visible(self.template.model, points)
        if self.illumination:
            scores = patch_ncc_scores(
                self.image,
                self._corners,
                self._bary,
                self._tri,
                self._values,
                points,
                visible,
                len(self.template.model.triangles),
            )
        else:
            scores = ncc_scores(
                self.image, self._corners, self._bary, self._tri, self._values, points, visible
            )
        self.evaluations += batch.shape[0]
        costs = 1.0 - np.nan_to_num(scores, nan=-1.0)
        return costs[0] if single else costs
