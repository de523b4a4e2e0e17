"""Content description: the personal wireframe, its texture and initial pose, in one file.

Units: pixels (texture coordinates), radians, unitless coefficients.

The engine sends this file ahead to the receiver once; afterwards only face animation parameters
travel. To keep it small the texture is the face's bounding box (plus a margin) from the
template, JPEG-coded, and the model travels as its personalised vertices and triangles with the
action units (the receiver animates; it never needs the shape units again).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uma.errors import FaceError
from uma.face.fit_points import PointFit, fit_points
from uma.face.geometry import project
from uma.face.model import FaceModel
from uma.face.npz import write_npz
from uma.face.points import read_points
from uma.failure import Failure

__all__ = ["ContentDescription", "describe", "read_points"]

MARGIN = 0.15  # of the face box, around the texture crop
JPEG_QUALITY = 90


@dataclass(frozen=True, eq=False)
class ContentDescription:
    """A personal model fitted to a template: `params` place `model` on `texture` (gray or BGR)."""

    model: FaceModel
    texture: np.ndarray
    params: np.ndarray
    shape: np.ndarray
    points: dict[str, tuple[float, float]]
    fit_rms_px: float
    origin_px: tuple[float, float] = (0.0, 0.0)  # where the texture's top-left sat in the image
    # The head ring (face-outline radii) the sender chose for the receiver from the clip's first
    # second (`uma.mbc.profile.with_sender_ring`); None: the codec profile's.
    head_ring_outlines: float | None = None

    def __bool__(self) -> bool:
        return True

    @property
    def gray(self) -> np.ndarray:
        """The texture's luma as the codecs see it (BT.601 limited range, `uma.face.colour`);
        a gray texture is its own luma."""
        if self.texture.ndim == 2:
            return self.texture
        cache = self.__dict__.setdefault("_luma", {})
        if "luma" not in cache:
            from uma.face.colour import bgr_to_luma

            cache["luma"] = bgr_to_luma(self.texture)
        return cache["luma"]

    def projected(self) -> np.ndarray:
        """The model's vertices on the texture, (N, 2) pixels."""
        return project(self.model, self.params)

    @property
    def size_bytes(self) -> int:
        """Bytes the receiver must get before the first animated frame (the saved file)."""
        return len(self.to_bytes())

    def to_bytes(self) -> bytes:
        """The file `save` writes: a deflated npz of JSON metadata, float32 vertices, float16
        action units, the parameters and the texture as JPEG."""
        import cv2

        ok, jpeg = cv2.imencode(".jpg", self.texture, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
        if not ok:
            raise FaceError("cannot JPEG-encode the texture")
        meta = {
            "name": self.model.name,
            "action_unit_names": list(self.model.action_unit_names),
            "shape_unit_names": list(self.model.shape_unit_names),
            "feature_points": self.model.feature_points,
            "points": {k: list(v) for k, v in self.points.items()},
            "fit_rms_px": self.fit_rms_px,
            "origin_px": list(self.origin_px),
        }
        if self.head_ring_outlines is not None:  # older files (and the sizes sent) unchanged
            meta["head_ring_outlines"] = float(self.head_ring_outlines)
        return write_npz(
            meta=np.frombuffer(json.dumps(meta, sort_keys=True).encode(), dtype=np.uint8),
            vertices=self.model.vertices.astype(np.float32),
            triangles=self.model.triangles.astype(np.uint16),
            action_units=self.model.action_units.astype(np.float16),
            params=self.params,
            shape=self.shape,
            texture_jpeg=jpeg.ravel(),
        )

    def save(self, path: str | Path) -> int:
        """Write the description (atomically); returns its size in bytes."""
        from uma.atomic import atomic_write_bytes

        data = self.to_bytes()
        atomic_write_bytes(path, data)
        return len(data)


MAX_RMS_FRAC = 0.06  # of scale_px (~6 mm on a face): worse than careless clicking


def _implausible(fit: PointFit) -> Failure | None:
    """Why a least-squares fit is not this face (a mislabelled or misplaced point), or None."""
    limit_px = MAX_RMS_FRAC * fit.params[2]
    if fit.rms_px > limit_px:
        worst = int(np.argmax(np.hypot(*fit.residuals_px.T)))
        return Failure(
            f"the points fit the model only to {fit.rms_px:.1f} px rms (limit {limit_px:.1f} px); "
            f"point {fit.names[worst]} is {np.hypot(*fit.residuals_px[worst]):.1f} px off: "
            "mislabelled or misplaced?"
        )
    return None


def describe(
    image: np.ndarray,
    points: Mapping[str, tuple[float, float]],
    *,
    model: FaceModel | None = None,
    crop: bool = True,
    ridge_px: float | None = None,
) -> ContentDescription | Failure:
    """Fit `model` (uma's wireframe by default) to `points` on `image` and cut out its texture
    (the face's box with a margin; with `crop=False` the whole image, `origin_px` (0, 0), for a
    receiver that renders over the template's own picture). `ridge_px` overrides the fit's
    penalty on shape and action coefficients (`uma.face.fit_points.RIDGE_PX`): larger keeps
    them nearer 0 where the points hardly tell units apart (mouth width against lip stretch)."""
    from uma.face.load import load_model

    model = model if model is not None else load_model()
    extra = {} if ridge_px is None else {"ridge_px": ridge_px}
    fit = fit_points(model, points, image_shape=image.shape[:2], **extra)
    if not fit:
        return fit
    assert isinstance(fit, PointFit)
    problem = _implausible(fit)
    if problem is not None:
        return problem
    personal = model.personalised(fit.shape)
    corners = project(personal, fit.params)
    low, high = corners.min(axis=0), corners.max(axis=0)
    margin = MARGIN * (high - low)
    x0, y0 = np.maximum(np.floor(low - margin), 0).astype(int)
    x1 = int(min(np.ceil(high[0] + margin[0]), image.shape[1]))
    y1 = int(min(np.ceil(high[1] + margin[1]), image.shape[0]))
    if not crop:
        x0, y0, x1, y1 = 0, 0, image.shape[1], image.shape[0]
    params = fit.params.copy()
    params[0] -= x0
    params[1] -= y0
    shifted = {k: (x - x0, y - y0) for k, (x, y) in points.items()}
    return ContentDescription(
        model=personal,
        texture=np.ascontiguousarray(image[y0:y1, x0:x1]),
        params=params,
        shape=fit.shape,
        points=shifted,
        fit_rms_px=fit.rms_px,
        origin_px=(float(x0), float(y0)),
    )
