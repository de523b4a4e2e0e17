"""The tracker's confidence gate: how much of the face no longer looks like the tracked face.

Units: grey levels; shares are fractions of the visible template pixels (0 to 1).

The fitting score (a correlation with the template) tells a face from no face when all of it
is gone, but a hand over half the face can leave the score unchanged or even raise it (a flat
occluder matches flat skin patches under per-patch photometry) while the fit slides off by
8-15 px. The gate keeps what the tracked face has looked like: the picture sampled at the
template's pixels under each accepted pose, as a running mean, and the usual size of a frame's
residual against it (its median absolute value, after one gain and offset). A frame whose
samples at the fitted pose depart from the mean by more than `outlier_k` times that size in
more than a share of the pixels has something in front of the face (or is not the face): the
tracker treats it as a lost track instead of drawing the model where it landed. Pixels that
depart adapt slowly, so an occluder that stays is not learnt as the face.
"""

from __future__ import annotations

import numpy as np

from uma.fit.cost import FitTemplate, batch_visible

__all__ = ["AppearanceGate"]

# The gate judges only once it has seen this many frames: the residual's size needs a few.
WARM_UP_FRAMES = 3
MIN_SCALE = 2.0  # grey levels: the residual size the gate never goes below (noise, blocking)


class AppearanceGate:
    """A running appearance of the tracked face over about `pixels` template pixels."""

    def __init__(
        self,
        template: FitTemplate,
        *,
        pixels: int = 1500,
        rate: float = 0.15,
        outlier_k: float = 3.0,
        blur_widths: float = 0.03,
    ):
        step = -(-template.raster.size // max(pixels, 1))
        self.template = template.subsampled(step)
        r = self.template.raster
        self._corners = np.ascontiguousarray(r.corners, dtype=np.int64)
        self._bary = np.ascontiguousarray(r.bary, dtype=np.float32)
        self._tri = np.asarray(r.tri)
        model = template.model
        self._vertices = np.ascontiguousarray(model.vertices, dtype=np.float64)
        units = model.action_units if model.n_actions else np.zeros((0,) + model.vertices.shape)
        self._units = np.ascontiguousarray(units, dtype=np.float64)
        self.rate = float(rate)
        # Blurred by this share of the face's width: a fit off by a pixel or two (as after a
        # re-initialisation) must not look like something in front of the face.
        self.blur_widths = float(blur_widths)
        self.outlier_k = float(outlier_k)
        self.reset()

    def reset(self) -> None:
        """Forget the face's appearance: the next accepted frame starts it again."""
        self.mean: np.ndarray | None = None
        self.scale = 0.0
        self.frames = 0  # accepted frames since the reset
        self._cached = None
        self._last_residual = None  # (sampling key, residual) of the last `outlier_share`

    def _samples(self, image: np.ndarray, params: np.ndarray, *, reuse: bool = False):
        # `accept` usually follows `outlier_share` on the same picture and pose: sample once.
        key = (id(image), params.tobytes())
        cached, self._cached = self._cached, None
        if reuse and cached is not None and cached[0] == key:
            self._cached = cached
            return cached[1]
        out = self._sample(image, params)
        self._cached = (key, out)
        return out

    def _sample(self, image: np.ndarray, params: np.ndarray):
        from uma.fit.cost import blurred
        from uma.fit.kernels import project_batch, sample_at

        points = project_batch(self._vertices, self._units, np.ascontiguousarray(params[None]))
        low, high = points[0].min(axis=0), points[0].max(axis=0)
        sigma = self.blur_widths * float(high[0] - low[0])
        # Only the face's box (and a margin for the blur) is blurred.
        margin = 3.0 * sigma + 2.0
        x0, y0 = (max(0, int(v - margin)) for v in low)
        x1 = min(image.shape[1], int(high[0] + margin) + 2)
        y1 = min(image.shape[0], int(high[1] + margin) + 2)
        if x1 - x0 < 4 or y1 - y0 < 4:
            return np.zeros(self._tri.size), np.zeros(self._tri.size, bool)
        crop = blurred(image[y0:y1, x0:x1], sigma)
        local = np.ascontiguousarray(points - np.array([x0, y0], np.float32))
        samples = sample_at(crop, self._corners, self._bary, local)[0].astype(np.float64)
        visible = batch_visible(self.template.model, points)[0][self._tri]
        # Only pixels that land in the picture: a face leaving it is not a covered face. Each
        # lands inside its triangle (weights within [0, 1] to float32's rounding): with every
        # vertex a pixel or more inside the picture, every one lands inside it.
        height, width = image.shape
        if low[0] >= 1 and low[1] >= 1 and high[0] <= width - 2 and high[1] <= height - 2:
            return samples, visible & np.isfinite(samples)
        where = np.einsum("kc,kcd->kd", self._bary, points[0][self._corners])
        inside = (where[:, 0] >= 0) & (where[:, 0] <= width - 1)
        inside &= (where[:, 1] >= 0) & (where[:, 1] <= height - 1)
        return samples, visible & inside & np.isfinite(samples)

    def _residual(self, samples: np.ndarray, visible: np.ndarray) -> np.ndarray | None:
        """Samples against the mean after one least-squares gain and offset (visible only)."""
        s, m = samples[visible], self.mean[visible]
        if s.size < 16 or s.std() < 1e-6:
            return None
        gain = float(np.mean((s - s.mean()) * (m - m.mean())) / s.var())
        return gain * (s - s.mean()) + m.mean() - m

    def outlier_share(self, image: np.ndarray, params: np.ndarray) -> float:
        """Share of the visible pixels at `params` that depart from the tracked appearance
        (0 before any frame was accepted; 1 when nothing can be compared)."""
        if self.mean is None or self.frames < WARM_UP_FRAMES:
            return 0.0
        samples, visible = self._samples(image, params)
        residual = self._residual(samples, visible & np.isfinite(self.mean))
        # `accept` on the same picture and pose uses the same mask and mean: keep the residual.
        self._last_residual = (self._cached[0], residual)
        if residual is None:
            return 1.0
        return float(np.mean(np.abs(residual) > self.outlier_k * max(self.scale, MIN_SCALE)))

    def accept(self, image: np.ndarray, params: np.ndarray) -> None:
        """Learn an accepted frame: departing pixels at a tenth of the rate."""
        samples, visible = self._samples(image, params, reuse=True)
        key, self._cached = self._cached[0], None
        # `outlier_share`'s residual on this picture and pose, when it computed one: only
        # `accept` changes the mean, and `known` below is the mask it used.
        last, self._last_residual = self._last_residual, None
        self.frames += 1
        if self.mean is None:
            self.mean = np.where(visible, samples, np.nan)
            self.scale = 0.0
            return
        known = visible & np.isfinite(self.mean)
        fresh = visible & ~known
        self.mean[fresh] = samples[fresh]
        if known.sum() < 16:
            return
        if last is not None and last[0] == key:
            residual = last[1]
        else:
            residual = self._residual(samples, known)
        if residual is None:
            return
        size = 1.4826 * float(np.median(np.abs(residual)))
        self.scale = size if self.scale == 0.0 else (1 - self.rate) * self.scale + self.rate * size
        departing = np.abs(residual) > self.outlier_k * max(self.scale, MIN_SCALE)
        rate = np.where(departing, 0.1 * self.rate, self.rate)
        # Move the mean towards the frame as seen through the same gain and offset.
        target = self.mean[known] + residual
        self.mean[known] += rate * (target - self.mean[known])
