"""Face detection front end: OpenCV's Viola-Jones Haar cascade proposes the face box.

Units: pixels. The cascade ships inside opencv-python-headless below version 5.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from uma.failure import Failure

__all__ = ["Box", "detect_face", "detect_faces", "face_of_points"]

# A point lies on a detected face when it falls inside the box grown by this share of the
# box's size on each side and twice that below (the cascade's box ends near the mouth; the chin
# point sits up to 0.2 of the box below it on the shipped clips and the 43 dlib faces).
NEAR_SHARE = 0.25
# Below this share of the points on any detected face, the points belong to no face here.
MIN_SHARE_ON_FACE = 0.5
# Clicked points span 0.6-0.9 of the cascade's box width on those faces.
SPAN_RANGE = (0.3, 1.5)


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
    faces = detect_faces(gray, min_size_px=min_size_px, neighbours=neighbours)
    if not faces:
        return faces
    return max(faces, key=lambda b: b.width * b.height)


def detect_faces(
    gray: np.ndarray, *, min_size_px: int = 24, neighbours: int = 4
) -> list[Box] | Failure:
    """Every frontal face in an 8-bit gray image, or a `Failure` saying why none."""
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
    return [Box(int(x), int(y), int(w), int(h)) for x, y, w, h in faces]


def face_of_points(
    faces: list[Box], points: dict[str, tuple[float, float]]
) -> tuple[Box, str | None] | Failure:
    """The detected face the points belong to and a warning when some lie away from it, or a
    `Failure` when no face holds most of them (points clicked on another picture)."""
    names = list(points)
    xy = np.array([points[n] for n in names], dtype=np.float64).reshape(-1, 2)
    if not faces or xy.size == 0:
        return Failure("no detected face to check the points against")

    def on(box: Box) -> np.ndarray:
        u = (xy[:, 0] - box.x) / box.width
        v = (xy[:, 1] - box.y) / box.height
        return (
            (u >= -NEAR_SHARE)
            & (u <= 1 + NEAR_SHARE)
            & (v >= -NEAR_SHARE)
            & (v <= 1 + 2 * NEAR_SHARE)
        )

    box = max(faces, key=lambda b: (int(on(b).sum()), b.width * b.height))
    inside = on(box)
    where = f"{box.x},{box.y} {box.width}x{box.height}"
    if inside.mean() < MIN_SHARE_ON_FACE:
        return Failure(
            f"the points lie on no detected face ({int(inside.sum())} of {len(names)} on the "
            f"nearest, at {where}): are they from another picture?"
        )
    warning = None
    if not inside.all():
        away = [n for n, ok in zip(names, inside, strict=True) if not ok]
        listed = ", ".join(away[:5]) + (", ..." if len(away) > 5 else "")
        warning = (
            f"{len(away)} of {len(names)} points ({listed}) lie away from the face detected at "
            f"{where}: are they from this picture?"
        )
    span = float(np.ptp(xy[:, 0])) / box.width
    if warning is None and not SPAN_RANGE[0] <= span <= SPAN_RANGE[1]:
        warning = (
            f"the points span {span:.2f} of the width of the face detected at {where} "
            f"(expected {SPAN_RANGE[0]}-{SPAN_RANGE[1]}): are they from this picture?"
        )
    return box, warning
