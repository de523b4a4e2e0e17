"""Face detection front end: OpenCV's Viola-Jones Haar cascade proposes the face box.

Units: pixels. The cascade ships inside opencv-python-headless below version 5.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from uma.failure import Failure

__all__ = [
    "Box",
    "detect_face",
    "detect_faces",
    "detect_any_faces",
    "face_of_points",
    "locate_points",
    "edge_cut_box",
]

# A point lies on a detected face when it falls inside the box grown by this share of the
# box's size on each side and twice that below (the cascade's box ends near the mouth; the chin
# point sits up to 0.2 of the box below it on the shipped clips and the 43 dlib faces).
NEAR_SHARE = 0.25
# Below this share of the points on any detected face, the points belong to no face here.
MIN_SHARE_ON_FACE = 0.5
# Clicked points span 0.6-0.9 of the cascade's box width on those faces.
SPAN_RANGE = (0.3, 1.5)
TYPICAL_SPAN = 0.75
# Points this near the picture's edge (in their own span) belong to a face the edge cuts: the
# cascade finds no face there (foreman's forehead lies above the picture).
EDGE_CUT_OF_SPAN = 0.25


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


@lru_cache(maxsize=4)
def _cascade(name: str = "haarcascade_frontalface_default.xml"):
    import cv2

    cascade = cv2.CascadeClassifier(cv2.data.haarcascades + name)
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
    key = (_digest(gray), min_size_px, neighbours)
    found = _FOUND.get(key)
    if found is None:
        faces = _cascade().detectMultiScale(
            cv2.equalizeHist(gray),
            scaleFactor=1.1,
            minNeighbors=neighbours,
            minSize=(min_size_px, min_size_px),
        )
        found = tuple(Box(int(x), int(y), int(w), int(h)) for x, y, w, h in faces)
        _FOUND[key] = found
        while len(_FOUND) > _FOUND_KEPT:
            del _FOUND[next(iter(_FOUND))]
    if not found:
        return Failure("no face detected")
    return list(found)


# What the cascade found, by picture: a looped clip (the real-video commute loops akiyo's 300
# frames 34 times, and the headline runs it with six engines in one process) asks again for the
# same pictures. The cascade is deterministic, so a picture's answer is kept; oldest dropped
# first beyond this many.
_FOUND: dict[tuple[bytes, int, int], tuple[Box, ...]] = {}
_FOUND_KEPT = 4096


def _digest(gray: np.ndarray) -> bytes:
    """A picture's identity: its size and a 128-bit BLAKE2 hash of its bytes."""
    import hashlib

    digest = hashlib.blake2b(np.ascontiguousarray(gray).data, digest_size=16)
    digest.update(np.asarray(gray.shape, dtype=np.int64).tobytes())
    return digest.digest()


# For checking where points lie, faces the frontal cascade misses count too: its second frontal
# cascade and the profile one (both ways), at 3 neighbours. On the 43 faces of the shared dlib
# files the default cascade alone misses 4 (crowded photographs); these together miss none,
# and accept no more of the astronaut's points moved off her face than the default does.
_ANY_CASCADES = (
    ("haarcascade_frontalface_default.xml", False),
    ("haarcascade_frontalface_alt2.xml", False),
    ("haarcascade_profileface.xml", False),
    ("haarcascade_profileface.xml", True),
)


def detect_any_faces(gray: np.ndarray, *, min_size_px: int = 24) -> list[Box]:
    """Every face, frontal or in profile, that OpenCV's cascades find in an 8-bit gray image
    (possibly none), for telling whether points lie on a face."""
    import cv2

    if gray.ndim != 2 or gray.dtype != np.uint8 or min(gray.shape) < min_size_px:
        return []
    equalised = cv2.equalizeHist(gray)
    mirrored = np.ascontiguousarray(equalised[:, ::-1])
    boxes = []
    for name, flip in _ANY_CASCADES:
        found = _cascade(name).detectMultiScale(
            mirrored if flip else equalised,
            scaleFactor=1.1,
            minNeighbors=3,
            minSize=(min_size_px, min_size_px),
        )
        for x, y, w, h in found:
            left = gray.shape[1] - x - w if flip else x
            boxes.append(Box(int(left), int(y), int(w), int(h)))
    return boxes


def face_of_points(
    faces: list[Box], points: dict[str, tuple[float, float]]
) -> tuple[Box, str | None] | Failure:
    """The face the points belong to and a warning when some lie away from it, or a `Failure`
    when no face holds most of them (points clicked on another picture). `faces` are the
    detector's boxes, plus the annotator's when a landmark file gives one (a face the cascade
    misses, turned away, is still a face)."""
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

    span_px = max(float(np.ptp(xy[:, 0])), 1e-9)

    def fit(box: Box) -> tuple[int, float]:
        # Most points on it first; then the box whose width suits the points' span best.
        return int(on(box).sum()), -abs(np.log(span_px / box.width / TYPICAL_SPAN))

    box = max(faces, key=fit)
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
    span = span_px / box.width
    if warning is None and not SPAN_RANGE[0] <= span <= SPAN_RANGE[1]:
        warning = (
            f"the points span {span:.2f} of the width of the face detected at {where} "
            f"(expected {SPAN_RANGE[0]}-{SPAN_RANGE[1]}): are they from this picture?"
        )
    return box, warning


def locate_points(
    gray: np.ndarray,
    points: dict[str, tuple[float, float]],
    *,
    frontal: list[Box] | None = None,
    annotated: Box | None = None,
) -> tuple[Box, str | None] | Failure:
    """`face_of_points` on the frontal cascade's faces (`frontal`, detected when None) and the
    annotator's box; only when they leave a doubt, again with every cascade's faces."""
    boxes = list(frontal if frontal is not None else detect_faces(gray) or [])
    boxes += [annotated] if annotated is not None else []
    placed = face_of_points(boxes, points)
    if placed and placed[1] is None:
        return placed
    wider = face_of_points(boxes + detect_any_faces(gray), points)
    if wider and (not placed or wider[1] is None):
        return wider
    return placed


def edge_cut_box(points: dict[str, tuple[float, float]], shape: tuple[int, ...]) -> Box | None:
    """The face box the clicked `points` imply (their span `TYPICAL_SPAN` of its width, square,
    about their centre) when they lie within `EDGE_CUT_OF_SPAN` of their span of an edge of a
    picture of `shape` (H, W, ...): a face the edge cuts, which no cascade finds; else None."""
    xy = np.array(list(points.values()), dtype=np.float64).reshape(-1, 2)
    if xy.shape[0] < 3:
        return None
    height, width = shape[:2]
    span_px = float(max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1])))
    near_px = EDGE_CUT_OF_SPAN * span_px
    low, high = xy.min(axis=0), xy.max(axis=0)
    if span_px <= 0 or min(low[0], low[1], width - 1 - high[0], height - 1 - high[1]) > near_px:
        return None
    side = int(round(span_px / TYPICAL_SPAN))
    cx, cy = (low + high) / 2.0
    return Box(int(round(cx - side / 2)), int(round(cy - side / 2)), side, side)
