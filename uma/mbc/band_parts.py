"""OpenCV's Telea inpainting of the plate's band, run part by part over the boxes the band's
separate parts lie in: the same pixels as one run over the whole picture, at less cost.

Units: pixels; planes (H, W) uint8, the band a (H, W) uint8 0/1 mask.

`cv2.inpaint` spends about a third of a CIF plate's fill on whole-picture passes (its flags,
distances and queue are set up over every pixel), and the rest on the band's pixels. A band
pixel's value reads only pixels within the inpainting radius of it (and one more for a
gradient), and the fast marching that orders the band never leaves the band and that reach:
parts of the band that lie more than `2 * PART_MARGIN_PX` columns apart never meet, so each
is inpainted within its own box (`PART_MARGIN_PX` about it, cut to the picture) and gives what
the whole picture gives there. A talking head's plate, whose background is a strip down the
middle, has two parts (the person's two sides) over about 60 % of the picture.
"""

from __future__ import annotations

import numpy as np

__all__ = ["band_boxes", "inpaint_band", "PART_MARGIN_PX"]

PART_MARGIN_PX = 8  # 2 radii and 2: a gradient's reach past what a radius of 3 reads


def band_boxes(
    band: np.ndarray, margin_px: int = PART_MARGIN_PX
) -> list[tuple[int, int, int, int]]:
    """The boxes (x0, y0, x1, y1) of `band`'s parts: runs of columns holding band pixels that
    lie more than 2 `margin_px` apart, each with its rows' extent, `margin_px` about it."""
    columns = np.flatnonzero(band.any(axis=0))
    if columns.size == 0:
        return []
    gaps = np.flatnonzero(np.diff(columns) > 2 * margin_px)
    starts = np.concatenate([columns[:1], columns[gaps + 1]])
    ends = np.concatenate([columns[gaps], columns[-1:]]) + 1
    height, width = band.shape
    boxes = []
    for a, b in zip(starts.tolist(), ends.tolist(), strict=True):
        rows = np.flatnonzero(band[:, a:b].any(axis=1))
        boxes.append((max(a - margin_px, 0), max(int(rows[0]) - margin_px, 0),
                      min(b + margin_px, width), min(int(rows[-1]) + 1 + margin_px, height)))  # fmt: skip
    return boxes


def inpaint_band(plane: np.ndarray, band: np.ndarray, radius_px: int) -> np.ndarray:
    """`cv2.inpaint(plane, band, radius_px, cv2.INPAINT_TELEA)`, run over `band_boxes` only
    (`radius_px` at most `(PART_MARGIN_PX - 2) // 2`)."""
    import cv2

    if 2 * radius_px + 2 > PART_MARGIN_PX:
        return cv2.inpaint(np.ascontiguousarray(plane), band, radius_px, cv2.INPAINT_TELEA)
    out = plane.copy()
    for x0, y0, x1, y1 in band_boxes(band):
        out[y0:y1, x0:x1] = cv2.inpaint(np.ascontiguousarray(plane[y0:y1, x0:x1]),
                                        np.ascontiguousarray(band[y0:y1, x0:x1]), radius_px,
                                        cv2.INPAINT_TELEA)  # fmt: skip
    return out
