"""The boxes the layered rendering draws over (`uma.mbc.layered_render`): a layer's, a mask's,
and the part of the picture a caller reads.

Units: pixels; boxes (x0, y0, x1, y1), x1 and y1 past the last column and row.
"""

from __future__ import annotations

import numpy as np

__all__ = ["points_box", "mask_box", "within", "clip_box", "crop", "ONLY_MARGIN_PX",
           "ONLY_MARGIN_SOFT_PX"]  # fmt: skip

# A drawing for a caller reading one box (`compose_layers`' `only`) is drawn over that box and
# this much about it: more than the layers' blurs reach (6 px), so the box's pixels are the same;
# with a softened outline, whose blur of the picture reaches 12 px more (`uma.mbc.outline`: a
# sigma of at most 4 px on uint8), the second.
ONLY_MARGIN_PX = 16
ONLY_MARGIN_SOFT_PX = 32


def points_box(points: np.ndarray, size: tuple[int, int]) -> tuple[int, int, int, int] | None:
    """The even-cornered, even-sized box (x0, y0, x1, y1) around `points` in the picture."""
    width, height = size
    x0 = max(int(np.floor(points[:, 0].min())) - 1, 0) // 2 * 2
    y0 = max(int(np.floor(points[:, 1].min())) - 1, 0) // 2 * 2
    x1 = min((int(np.ceil(points[:, 0].max())) + 3) // 2 * 2, width)
    y1 = min((int(np.ceil(points[:, 1].max())) + 3) // 2 * 2, height)
    if x1 - x0 < 2 or y1 - y0 < 2:
        return None
    return x0, y0, x1, y1


def mask_box(mask: np.ndarray, margin: int = 0) -> tuple[int, int, int, int] | None:
    """The even-cornered, even-sized box (x0, y0, x1, y1) around `mask`'s pixels, `margin`
    pixels wider on every side (clamped to the picture); None when the mask is empty."""
    import cv2

    x, y, w, h = cv2.boundingRect(mask.view(np.uint8))
    if w == 0 or h == 0:
        return None
    height, width = mask.shape
    x0, y0 = max(x - margin, 0) // 2 * 2, max(y - margin, 0) // 2 * 2
    x1 = min((x + w + margin + 1) // 2 * 2, width)
    y1 = min((y + h + margin + 1) // 2 * 2, height)
    return x0, y0, x1, y1


def within(box, clip, far_only: bool = False):
    """`box` (x0, y0, x1, y1) cut to `clip` (None: `box` as it is); `far_only`: its right
    and bottom sides only (a warp's box keeps its corner: OpenCV's fixed-point warp rounds
    each pixel's position by it); None when nothing is left."""
    if box is None or clip is None:
        return box
    x0, y0, x1, y1 = box
    if not far_only:
        x0, y0 = max(x0, clip[0]), max(y0, clip[1])
    x1, y1 = min(x1, clip[2]), min(y1, clip[3])
    return (x0, y0, x1, y1) if x1 > x0 and y1 > y0 else None


def clip_box(only, face: np.ndarray, margin_px: int = ONLY_MARGIN_PX):
    """The box every layer is drawn over for a caller reading `only(face)`'s box alone: that
    box and `margin_px` about it (even, inside the picture); None: the whole picture."""
    box = None if only is None else only(face)
    if box is None:
        return None
    height, width = face.shape
    m = int(margin_px)
    x0, y0 = max(box[0] - m, 0) // 2 * 2, max(box[1] - m, 0) // 2 * 2
    return x0, y0, min(box[2] + m + 1, width) // 2 * 2, min(box[3] + m + 1, height) // 2 * 2


def crop(picture: np.ndarray, box) -> np.ndarray:
    """`picture`'s (H, W) pixels in `box` (x0, y0, x1, y1)."""
    return picture[box[1] : box[3], box[0] : box[2]]
