"""The camera's motion, as the engine measures it: the background's shift from the reference.

Units: pixels (x right, y down), the shift that carries a background pixel of the reference to
where it lies in the frame (`uma.mbc.layers.CAMERA_NAMES`).

A hand-held camera moves the whole scene; the receiver's plate (the background it knows) holds
still unless told. The engine aligns the reference's background (its pixels outside the person,
kept `PERSON_MARGIN_OF_WIDTH` away from the person's outline so a person moving over them
does not pull the answer) with its newest picture by OpenCV's enhanced correlation (ECC, a
translation at half resolution, started from the last answer) and keeps its answer only if it
brings the background nearer the picture than no motion does (the median absolute difference
over those pixels down by `MIN_GAIN`: a window with scenery passing, or the person moving over
the background, can pull the alignment where the background did not go). A shift shorter than
`HOLD_PX` is held at zero: a still camera (akiyo) sends zeros and draws the plate unmoved.
"""

from __future__ import annotations

import numpy as np

__all__ = ["CameraAligner", "HOLD_PX"]

HOLD_PX = 0.75  # a shorter shift is no camera motion (a still camera's noise)
MIN_GAIN = 0.9  # a shift must bring the background's median difference to this much of still
PERSON_MARGIN_OF_WIDTH = 0.04  # of the picture's width, around the reference's person
_MIN_BACKGROUND_OF_PICTURE = 0.05
_ITERATIONS = 30
_EPSILON = 1e-3


class CameraAligner:
    """The camera's shift against one reference, at half resolution: `prepare` with the
    reference's half-resolution luma and its person mask (full resolution), then `measure`."""

    def __init__(self) -> None:
        self.last = np.zeros(2)
        self._template = None

    def prepare(self, template: np.ndarray, person: np.ndarray) -> None:
        """A new reference: `template` its luma at half resolution (float32), `person` the
        person's mask at full resolution; the shift starts again from zero."""
        import cv2

        height, width = person.shape
        radius = max(1, int(round(PERSON_MARGIN_OF_WIDTH * width / 2)))
        half = cv2.resize(person.view(np.uint8), (width // 2, height // 2),
                          interpolation=cv2.INTER_NEAREST)  # fmt: skip
        kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1,) * 2)
        background = (1 - cv2.dilate(half, kernel)).astype(np.uint8)
        self._template = (template, background)
        self.last = np.zeros(2)

    def measure(self, picture: np.ndarray) -> np.ndarray:
        """The camera's shift (px, full resolution) to `picture` (half-resolution luma,
        float32 or uint8); the last answer again when the alignment fails, zero when it is
        shorter than `HOLD_PX`."""
        import cv2

        if self._template is None:
            return self.last
        template, background = self._template
        if background.mean() < _MIN_BACKGROUND_OF_PICTURE:
            return self.last
        start = np.array([[1, 0, self.last[0] / 2], [0, 1, self.last[1] / 2]], np.float32)
        criteria = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, _ITERATIONS, _EPSILON)
        try:
            _, warp = cv2.findTransformECC(template, picture.astype(np.float32), start,
                                           cv2.MOTION_TRANSLATION, criteria, background, 3)  # fmt: skip
        except cv2.error:
            return self.last
        shift = 2.0 * warp[:, 2].astype(np.float64)
        height, width = template.shape
        if not np.all(np.isfinite(shift)) or np.any(np.abs(shift) > (width / 2, height / 2)):
            return self.last
        if float(np.hypot(*shift)) < HOLD_PX:
            self.last = np.zeros(2)
        elif _difference(template, picture, background, shift) < MIN_GAIN * _difference(
            template, picture, background, np.zeros(2)
        ):
            self.last = shift
        else:
            self.last = np.zeros(2)
        return self.last


def _difference(template, picture, background, shift) -> float:
    """The median absolute difference (levels) over `background` between `template` and
    `picture` read at the `shift` (full-resolution px) from it."""
    import cv2

    height, width = template.shape
    matrix = np.array([[1.0, 0.0, shift[0] / 2], [0.0, 1.0, shift[1] / 2]])
    moved = cv2.warpAffine(picture.astype(np.float32), matrix, (width, height),
                           flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                           borderMode=cv2.BORDER_REPLICATE)  # fmt: skip
    return float(np.median(np.abs(moved - template)[background > 0]))
