"""The face region of each source frame, for face-region quality scores.

Units: pixels; a box is (x, y, width, height) inside the frame. The box is a pure function of
the source: for the talking head, the bounding box of its ground-truth projected model points
plus a margin of `MARGIN` of the box's size on each side; for a video file or raw YUV, OpenCV's
Haar face detector, run once per distinct source frame (a looped clip repeats its frames, so
detections are cached by the clip's frame index), and where it finds no face the last box it
found (none before the first: that frame has no face score); for the synthetic pattern, none.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator

import numpy as np

from uma.face.detect import Box

__all__ = ["FaceBoxes", "face_mode", "points_box", "MARGIN"]

MARGIN = 0.1  # of the box's width (height) added left and right (above and below)


def points_box(
    points: np.ndarray, width: int, height: int, *, margin: float = MARGIN
) -> Box | None:
    """The bounding box of `points` (N, 2) widened by `margin` a side, clipped to the frame."""
    points = np.asarray(points, dtype=np.float64)
    finite = np.isfinite(points)
    if not finite.all():  # the usual all-finite set is taken whole
        points = points[finite.all(axis=1)]
    if points.size == 0:
        return None
    # Python floats from here: the same double arithmetic without numpy's scalar overhead.
    (x0, y0), (x1, y1) = points.min(axis=0).tolist(), points.max(axis=0).tolist()
    dx, dy = margin * (x1 - x0), margin * (y1 - y0)
    left, top = max(0, math.floor(x0 - dx)), max(0, math.floor(y0 - dy))
    right, bottom = min(width, math.ceil(x1 + dx) + 1), min(height, math.ceil(y1 + dy) + 1)
    if right <= left or bottom <= top:
        return None
    return Box(left, top, right - left, bottom - top)


def face_mode(source) -> str:
    """How `source`'s face region is found: "truth", "detect" or "none"."""
    mode = getattr(source, "face_mode", None)
    if mode is not None:
        return mode
    if callable(getattr(source, "ground_truth", None)):
        return "truth"
    if getattr(source, "name", None) == "pattern":
        return "none"
    return "detect"


class FaceBoxes:
    """Face boxes of a source's frames in the order they are read; `wrap` records them."""

    def __init__(self, source) -> None:
        self.source = source
        self.mode = face_mode(source)
        self.width, self.height = source.width, source.height
        self.clip_frames = getattr(source, "clip_frames", None)
        self.boxes: list[Box | None] = []
        self._detected: dict[int, Box | None] = {}
        self._last: Box | None = None

    def wrap(self, frames: Iterable[np.ndarray]) -> Iterator[np.ndarray]:
        """Yield `frames` unchanged, appending each one's face box to `self.boxes`."""
        for frame in frames:
            self.boxes.append(self.box(len(self.boxes), frame))
            yield frame

    def box(self, index: int, frame: np.ndarray) -> Box | None:
        """The face box of the `index`-th frame read (`frame`, YUV 4:2:0)."""
        if self.mode == "none":
            return None
        if self.mode == "truth":
            return points_box(self.source.ground_truth(index)["points"], self.width, self.height)
        clip_index = index % self.clip_frames if self.clip_frames else index
        if clip_index not in self._detected:
            from uma.face.detect import detect_face

            found = detect_face(np.ascontiguousarray(frame[: self.height]))
            self._detected[clip_index] = found if found else None
        found = self._detected[clip_index]
        if found is not None:
            self._last = found
        return self._last
