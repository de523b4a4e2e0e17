"""The fitting cost: how well the template, warped by candidate parameters, matches an image.

Units: pixels; parameters as in `uma.face.geometry` ([tx_px, ty_px, scale_px, rx_rad, ry_rad,
rz_rad, action units...]). Cost = 1 - normalised correlation coefficient over the template's
visible pixels (0 for a perfect match, up to 2), optionally after illumination compensation
(each triangle patch normalised to zero mean and unit variance in both images). Candidates are
evaluated in batches by compiled kernels (`uma.fit.kernels`); every evaluation is counted.
A cost may look at blurred copies of both images (`blur_px`, the Gaussian's sigma): a smoother
landscape with a wider basin, for the coarse global search. With `band_px` it looks at the
band-pass of the log intensity instead (the Gaussian of `blur_px` minus that of `band_px`): light
multiplies the albedo, so in the log image a change of light that varies slowly over the face
becomes a slowly varying offset, which the band-pass removes; the eyes, brows, nose and mouth
remain. It is what lets the global search through harsh side light.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.face.geometry import project, visible_triangles
from uma.face.model import FaceModel
from uma.face.render import Raster, barycentric_affine, rasterize

__all__ = ["FitTemplate", "Cost", "batch_visible", "blurred", "prepared"]

# Log-intensity band-pass values are scaled by this so they span tens of units, like grey levels
# (the kernels' flatness checks are absolute).
_LOG_SCALE = 100.0
_MAX_VIEWS = 16  # prepared views kept per template


def blurred(image: np.ndarray, sigma_px: float) -> np.ndarray:
    """`image` as contiguous float32, smoothed by a Gaussian of `sigma_px` when positive."""
    out = np.ascontiguousarray(image, dtype=np.float32)
    if sigma_px > 0:
        import cv2

        out = cv2.GaussianBlur(out, (0, 0), float(sigma_px), borderType=cv2.BORDER_REPLICATE)
    return out


def prepared(image: np.ndarray, blur_px: float = 0.0, band_px: float = 0.0) -> np.ndarray:
    """`image` as a cost sees it (float32): blurred by `blur_px`, or with `band_px` > `blur_px`,
    the band-pass of log(1 + intensity) between the two Gaussians."""
    if band_px <= 0:
        return blurred(image, blur_px)
    if band_px <= blur_px:
        raise ValueError(f"band-pass: band_px must exceed blur_px, got {band_px} <= {blur_px}")
    log = np.log1p(np.maximum(np.asarray(image, dtype=np.float32), 0.0))
    return _LOG_SCALE * (blurred(log, blur_px) - blurred(log, band_px))


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
        if raster.inside is not None:
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

    def smoothed(self, sigma_px: float, band_px: float = 0.0) -> FitTemplate:
        """The same pixels with their values read from the template image as `prepared` makes
        it. Kept per (sigma, band): SAABs asks for the same few views of a template on every
        frame (its stages are fractions of the template's own face width)."""
        if sigma_px <= 0 and band_px <= 0:
            return self
        cache = self.__dict__.setdefault("_views", {})
        key = (float(sigma_px), float(band_px))
        if key not in cache:
            if len(cache) >= _MAX_VIEWS:
                cache.pop(next(iter(cache)))
            image = prepared(self.image, sigma_px, band_px)
            values = image[self.raster.ys, self.raster.xs].astype(np.float32)
            cache[key] = FitTemplate(self.model, self.params, image, self.raster, values)
        return cache[key]

    @property
    def face_width_px(self) -> float:
        """The face's width at the template's pose (kept: the template is immutable)."""
        width = self.__dict__.get("_face_width_px")
        if width is None:
            width = float(np.ptp(project(self.model, self.params)[:, 0]))
            self.__dict__["_face_width_px"] = width
        return width


def batch_visible(model: FaceModel, points: np.ndarray) -> np.ndarray:
    """Front-facing triangles for projected points (B, N, 2) -> (B, T) bool."""
    from uma.fit.kernels import front_facing

    out = np.empty((points.shape[0], len(model.triangles)), bool)
    front_facing(points, model.triangles, out)  # compiled: (b - a) x (c - a) < 0, per triangle
    return out


@dataclass(frozen=True, eq=False)
class _Layout:
    """The template's pixels as the kernel reads them: grouped by triangle, with each
    triangle's map from template position to barycentric weights."""

    order: np.ndarray  # (K,) raster index of each kernel pixel
    pixels: np.ndarray  # (K, 2) float64 template x, y
    runs: np.ndarray  # (R, 3) triangle, first, end
    inverse: np.ndarray  # (T, 3, 3)

    @classmethod
    def of(cls, template: FitTemplate, step: int = 1) -> _Layout:
        """Cached on the raster (immutable), per placement and thinning step."""
        r = template.raster
        cache = r.__dict__.setdefault("_fit_layouts", {})
        key = (template.params.tobytes(), step)
        if key not in cache:
            # Every n-th pixel in the raster's own (row) order, so each patch keeps its share.
            rows = np.arange(0, r.size, step)
            order = rows[np.argsort(r.tri[rows], kind="stable")]
            tri = r.tri[order].astype(np.int64)
            if tri.size:
                starts = np.flatnonzero(np.r_[True, tri[1:] != tri[:-1]])
                ends = np.r_[starts[1:], tri.size]
                runs = np.stack([tri[starts], starts, ends], axis=1)
            else:
                runs = np.zeros((0, 3), dtype=np.int64)
            points = project(template.model, template.params)
            cache[key] = cls(
                order=order,
                pixels=np.ascontiguousarray(np.stack([r.xs, r.ys], axis=1)[order], np.float64),
                runs=np.ascontiguousarray(runs, dtype=np.int64),
                inverse=np.ascontiguousarray(
                    barycentric_affine(points, template.model.triangles), dtype=np.float64
                ),
            )
        return cache[key]


class Cost:
    """1 - correlation between the template and `image` warped by each candidate; counts
    evaluations. `illumination` compensates gain and offset per triangle patch (True), or mixes
    the compensated and plain scores with that weight (a float in [0, 1]); `blur_px` smooths
    both images first (the template's values are re-read from its blurred image), and with
    `band_px` both are band-passed log images (`prepared`). `template_px` (blur, band) views the
    template differently when its face is another size than the image's (the same filter
    relative to each face); by default it is viewed as the image."""

    def __init__(
        self,
        template: FitTemplate,
        image: np.ndarray,
        *,
        illumination: bool | float = False,
        blur_px: float = 0.0,
        band_px: float = 0.0,
        template_px: tuple[float, float] | None = None,
    ):
        weight = float(illumination)
        if not 0.0 <= weight <= 1.0:
            raise ValueError(
                f"illumination: expected a bool or a weight in [0, 1], got {illumination}"
            )
        self.template = template.smoothed(*(template_px or (blur_px, band_px)))
        self.image = prepared(image, blur_px, band_px)
        self.illumination = weight
        self.blur_px = float(blur_px)
        self.band_px = float(band_px)
        self.evaluations = 0
        model = template.model
        self._vertices = np.ascontiguousarray(model.vertices, dtype=np.float64)
        units = model.action_units
        if units is None or len(units) == 0:
            units = np.zeros((0,) + model.vertices.shape)
        self._units = np.ascontiguousarray(units, dtype=np.float64)
        self._triangles = np.ascontiguousarray(model.triangles, dtype=np.int64)
        self._layout = _Layout.of(template)
        self._values = np.ascontiguousarray(self.template.values[self._layout.order], np.float32)
        self.n_params = 6 + self._units.shape[0]
        self.pixels = int(self._layout.order.size)

    def thinned(self, pixels: int) -> Cost:
        """This cost on every n-th template pixel, so that at most `pixels` remain."""
        step = -(-self.template.raster.size // max(pixels, 1))
        if step <= 1:
            return self
        out = Cost.__new__(Cost)
        out.__dict__.update(self.__dict__)
        out._layout = _Layout.of(self.template, step)
        out._values = np.ascontiguousarray(self.template.values[out._layout.order], np.float32)
        out.pixels = int(out._layout.order.size)
        out.evaluations = 0
        return out

    def __call__(self, params: np.ndarray) -> np.ndarray:
        """Costs of candidates (B, P) -> (B,), or of one (P,) -> a 0-d array."""
        params = np.asarray(params, dtype=np.float64)
        single = params.ndim == 1
        batch = params[None] if single else params
        if not batch.flags.c_contiguous:
            batch = np.ascontiguousarray(batch)
        if batch.shape[-1] != self.n_params:
            raise ValueError(f"expected {self.n_params} parameters, got {batch.shape[-1]}")
        self.evaluations += batch.shape[0]
        # SAABs calls this once per annealing step: the usual all-finite batch takes one check.
        if np.isfinite(batch).all():
            costs = 1.0 - self._scores(batch)
        else:
            costs = np.full(batch.shape[0], 2.0)
            finite = np.isfinite(batch).all(axis=1)
            if finite.any():
                costs[finite] = 1.0 - self._scores(np.ascontiguousarray(batch[finite]))
        return costs[0] if single else costs

    def _scores(self, batch: np.ndarray) -> np.ndarray:
        """Scores of a contiguous batch of finite candidates; a non-finite score counts as -1."""
        from uma.fit.kernels import project_batch, scores

        points = project_batch(self._vertices, self._units, batch)
        layout = self._layout
        score = scores(
            self.image,
            layout.pixels,
            layout.inverse,
            layout.runs,
            self._values,
            points,
            self._triangles,
            self.illumination,
        )
        if not np.isfinite(score).all():
            score = np.where(np.isfinite(score), score, -1.0)
        return score
