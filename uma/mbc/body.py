"""The torso's motion, as the engine measures it: a 2-D rigid motion of the reference's torso.

Units: pixels; body motion as `uma.mbc.layers.BODY_NAMES` (shift px, rotation rad)
about the torso's anchor (the reference's chin).

The engine holds what the receiver renders from (its mirror, a layered
`uma.mbc.scene_render.SceneRenderer`): the reference picture and the torso's pixels on it.
`BodyTracker.measure` aligns that torso with the engine's newest picture by OpenCV's enhanced
correlation (ECC, a rigid motion at half resolution over the torso's pixels, started from
the last frame's answer). A frame it cannot align (no
texture, no convergence, an absurd answer) gives a `BodyFailure` with its reason; the caller
sends the last good motion again.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.mbc.camera import CameraAligner
from uma.mbc.layers import N_BODY, N_TORSO, NO_BODY_MOTION, body_matrix, body_problem, rigid_of

__all__ = ["BodyTracker", "BodyFailure"]

_ITERATIONS = 20
_EPSILON = 1e-3
_MIN_TORSO_PIXELS = 200  # at half resolution
_BELOW_CHIN_OF_HEIGHT = 0.05
# A torso whose pixels (half resolution) differ from those of the last aligned picture by
# less than this mean (luma levels) has not moved: the last motion stands, no alignment.
STILL_LEVELS = 0.75
# The alignment's template is the reference's rows holding the torso and this many rows (half
# resolution) above and below (the torso's pixels move by the body motion as the alignment
# goes): every iteration warps only those rows instead of the whole picture.
TEMPLATE_MARGIN_ROWS = 16


@dataclass(frozen=True)
class BodyFailure:
    """No body motion for this frame; false, with the reason."""

    reason: str

    def __bool__(self) -> bool:
        return False


class BodyTracker:
    """Measures the torso's motion against one renderer's reference (with `camera`, the
    camera's too: `uma.mbc.camera`, `last` then holds both); `reset` when the reference
    changes (a new reference starts from no motion)."""

    def __init__(self, *, camera: bool = False) -> None:
        self._n = N_BODY if camera else N_TORSO
        self.last = NO_BODY_MOTION[: self._n].copy()
        self._key = None
        self._template = None
        self._aligned = None  # the half-resolution picture the last motion was measured on
        self.camera = CameraAligner() if camera else None

    def reset(self) -> None:
        self.last = NO_BODY_MOTION[: self._n].copy()
        self._key = None
        self._aligned = None

    def _prepare(self, renderer) -> None:
        import cv2

        key = (id(renderer), renderer.reference_serial)
        if key == self._key:
            return
        height = renderer.size[1]
        half = (renderer.size[0] // 2, height // 2)
        luma = cv2.resize(renderer.reference[:height], half, interpolation=cv2.INTER_AREA)
        mask = renderer.torso_mask.copy()
        # Below the chin only: the head moves on its own and would pull the torso along.
        mask[: max(int(renderer.anchor[1] + _BELOW_CHIN_OF_HEIGHT * height), 0)] = 0
        mask = cv2.resize(mask, half, interpolation=cv2.INTER_NEAREST)
        self._template = (luma.astype(np.float32), mask.astype(np.uint8))
        rows = np.flatnonzero(mask.any(axis=1))
        top = max(int(rows[0]) - TEMPLATE_MARGIN_ROWS, 0) if rows.size else 0
        bottom = min(int(rows[-1]) + 1 + TEMPLATE_MARGIN_ROWS, half[1]) if rows.size else half[1]
        self._rows = (top, np.ascontiguousarray(self._template[0][top:bottom]))
        if self.camera is not None:
            self.camera.prepare(self._template[0], renderer.person_mask)
        self._key = key
        self.last = NO_BODY_MOTION[: self._n].copy()
        self._aligned = None

    def measure(self, renderer, luma: np.ndarray) -> np.ndarray | BodyFailure:
        """The torso's motion from `renderer`'s reference to `luma` (H, W), or a
        `BodyFailure` (the last good motion stays in `last`)."""
        import cv2

        if not getattr(renderer, "layered", False):
            return BodyFailure("body motion: the renderer draws no layers")
        self._prepare(renderer)
        _, mask = self._template
        if int(np.count_nonzero(mask)) < _MIN_TORSO_PIXELS:
            return BodyFailure("body motion: too little torso in the picture")
        anchor = renderer.anchor
        start = body_matrix(self.last, anchor).astype(np.float32)
        start[:, 2] *= 0.5  # half resolution: the same map on halved coordinates
        width, height = renderer.size
        picture = cv2.resize(luma, (width // 2, height // 2), interpolation=cv2.INTER_AREA)
        if self.camera is not None:
            self.last = self.last.copy()
            self.last[N_TORSO:] = self.camera.measure(picture)
        if self._aligned is not None and self._still(picture, mask):
            return self.last  # the torso did not change since it was last aligned
        criteria = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, _ITERATIONS, _EPSILON)
        top, rows = self._rows  # the template's rows about the torso: its row 0 is row `top`
        start = start.astype(np.float64)
        start[:, 2] += start[:, 1] * top
        try:
            _, warp = cv2.findTransformECC(
                rows, picture.astype(np.float32), start.astype(np.float32),
                cv2.MOTION_EUCLIDEAN, criteria, mask, 3,
            )  # fmt: skip
        except cv2.error as err:
            return BodyFailure(f"body motion: no alignment ({str(err).strip().splitlines()[-1]})")
        warp = warp.astype(np.float64)
        warp[:, 2] -= warp[:, 1] * top
        warp[:, 2] *= 2.0
        body = np.concatenate([rigid_of(warp, anchor), self.last[N_TORSO:]])
        problem = body_problem(body, renderer.size)
        if problem:
            return BodyFailure(problem)
        self.last = body
        self._aligned = picture
        return body

    def _still(self, picture: np.ndarray, mask: np.ndarray) -> bool:
        """Whether `picture`'s torso pixels (`mask`, half resolution) are those of the last
        aligned picture within `STILL_LEVELS` on average."""
        import cv2

        change = cv2.mean(cv2.absdiff(picture, self._aligned), mask=mask)[0]
        return change < STILL_LEVELS
