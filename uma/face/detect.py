"""Face detection front end: OpenCV's Viola-Jones Haar cascade proposes the face box.

Units: pixels. The cascade ships inside opencv-python-headless below version 5.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from uma.failure import Failure

__all__ = ["Box", "detect_face"]


@dataclass(frozen=True)
class Box:
    x: int
    y: int
    width: int
    height: int

    @property
    def centre(self) -> tuple[float, float]:
        return self.x + self.width / 2, self.y + self.height / 2

    def __bool__(self) -> bool:
        return True


@lru_cache(maxsize=1)
def _cascade():
    import cv2

    cascade = cv2.CascadeClassifier(cv2.data.haarcascades + "haarcascade_frontalface_default.xml")
    if cascade.empty():
        raise RuntimeError(
            "OpenCV's frontal face cascade is missing (opencv-python-headless >= 5?)"
        )
    return cascade


def detect_face(gray: np.ndarray, *, min_size_px: int = 24, neighbours: int = 4) -> Box | Failure:
    """The largest frontal face in an 8-bit gray image, or a `Failure` saying why none."""
    import cv2

    if gray.ndim != 2 or gray.dtype != np.uint8:
        return Failure(f"face detection needs an 8-bit gray image, got {gray.dtype} {gray.shape}")
    if gray.shape[0] < min_size_px or gray.shape[1] < min_size_px:
        return Failure(f"image {gray.shape[1]}x{gray.shape[0]} is smaller than the smallest face")
    if float(gray.std()) < 2.0:
        return Failure("image is flat or saturated: no face can be found")
    faces = _cascade().detectMultiScale(
        cv2.equalizeHist(gray),
        scaleFactor=1.1,
        minNeighbors=neighbours,
        minSize=(min_size_px, min_size_px),
    )
    if len(faces) == 0:
        return Failure("no face detected")
    x, y, w, h = max(faces, key=lambda f: f[2] * f[3])
    return Box(int(x), int(y), int(w), int(h))
