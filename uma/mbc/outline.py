"""The person's outline as far as the receiver can know it: softened where the head has moved.

Units: pixels; pictures are planar YUV 4:2:0 (H * 3 // 2, W) uint8.

The receiver draws the head, its halo and the plate around them from one old picture moved by
a rigid pose; the further the head has moved from that picture, the less the outline it draws
(hair, the headrest behind it, what the head uncovers) matches the one the camera sees. Where
a pixel can be one of several things, the picture that errs least is their average: a band
about the edge of the drawn head and halo (twice as deep inside as outside, never the face's
own pixels), as wide as a share of the head's move, is blended toward its own blur. docs/mbc.md ("Issue 27, session mbcq") has the
error's split by region that chose this and the settings' measurements.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "soften_outline",
    "outline_band_px",
    "OUTLINE_OF_MOVE",
    "OUTLINE_MAX_PX",
    "OUTLINE_MAX_OF_WIDTH",
]

OUTLINE_OF_MOVE = 0.45  # the band's half-width, as a share of the head's move (px per px)
OUTLINE_MAX_PX = 8  # the widest band's half-width
OUTLINE_MAX_OF_WIDTH = 0.06  # and at most this share of the drawn head's (and halo's) width
# The band reaches this many half-widths inside the head and halo (their rim, never the face).
OUTLINE_INNER_OF_BAND = 2.0
OUTLINE_SIGMA_OF_BAND = 0.5  # the blur's sigma, as a share of the band's half-width
_EDGE_SIGMA_PX = 1.0  # the band's own edge fades over this


def outline_band_px(moved_px: float, width_px: float = np.inf) -> int:
    """The band's half-width (px) for a head `width_px` wide (with its halo) moved
    `moved_px` from the reference; 0: none."""
    if not np.isfinite(moved_px) or moved_px <= 0.0:
        return 0
    cap = min(OUTLINE_MAX_PX, OUTLINE_MAX_OF_WIDTH * width_px)
    return int(round(min(OUTLINE_OF_MOVE * moved_px, cap)))


def _box(
    rect: tuple[int, int, int, int], shape: tuple[int, int], margin: int
) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) of the bounding `rect` (x, y, w, h) widened by `margin`, even, inside a
    picture of `shape` (H, W)."""
    x, y, w, h = rect
    height, width = shape
    x0, y0 = max(x - margin, 0) // 2 * 2, max(y - margin, 0) // 2 * 2
    x1 = min(-(-(x + w + margin) // 2) * 2, width)
    y1 = min(-(-(y + h + margin) // 2) * 2, height)
    return x0, y0, x1, y1


def soften_outline(
    out: np.ndarray, person: np.ndarray, face: np.ndarray, moved_px: float, chroma: bool = True
) -> None:
    """Blend, in place, the band of `outline_band_px(moved_px)` about the edge of `person` (H, W:
    the drawn head and halo) in `out` toward its blur, the face's own pixels (`face`, H, W
    bool) excepted; chroma alike at half resolution (left as it is without `chroma`)."""
    import cv2

    height = person.shape[0]
    rect = cv2.boundingRect(person.view(np.uint8))  # of the mask's pixels: no list of them
    if rect[2] == 0 or out.shape[0] != height * 3 // 2:
        return
    band_px = outline_band_px(moved_px, rect[2])
    if band_px < 1:
        return
    sigma = max(OUTLINE_SIGMA_OF_BAND * band_px, 0.8)
    x0, y0, x1, y1 = _box(rect, person.shape, band_px + int(np.ceil(3 * sigma)) + 4)
    weight, half = _half_res_weight(person[y0:y1, x0:x1], band_px)
    weight[face[y0:y1, x0:x1]] = 0.0
    luma = out[y0:y1, x0:x1]
    _toward(luma, cv2.GaussianBlur(luma, (0, 0), sigma), weight)
    if not chroma:
        return
    planes = out[height:].reshape(2, height // 2, -1)[:, y0 // 2 : y1 // 2, x0 // 2 : x1 // 2]
    half[face[y0:y1:2, x0:x1:2]] = 0.0
    for plane in planes:
        _toward(plane, cv2.GaussianBlur(plane, (0, 0), max(sigma / 2, 0.5)), half)


def _weight(
    person: np.ndarray, band_px: float, edge_sigma_px: float = _EDGE_SIGMA_PX
) -> np.ndarray:
    """The band's weights (float32, the box's shape) about the edge of `person` (a box of the
    mask): within `band_px` outside, `OUTLINE_INNER_OF_BAND` times it inside, its edge faded
    over `edge_sigma_px`."""
    import cv2

    inside = person.astype(np.uint8)
    # Distances to the edge from either side (cheaper than morphology with wide kernels).
    outside_px = cv2.distanceTransform(1 - inside, cv2.DIST_L2, 3)
    inside_px = cv2.distanceTransform(inside, cv2.DIST_L2, 3)
    band = (outside_px <= band_px) & (inside_px <= OUTLINE_INNER_OF_BAND * band_px)
    return cv2.GaussianBlur(band.astype(np.float32), (0, 0), edge_sigma_px)


def _half_res_weight(person: np.ndarray, band_px: int) -> tuple[np.ndarray, np.ndarray]:
    """`_weight` found on every other pixel (a quarter of the pixels; distances and fade in
    half pixels), then enlarged (bilinear) to the box: (the box's weights, the half-size ones,
    for chroma). The pictures move by hundredths of a dB against the full-size weights
    (docs/mbc.md, branch mbc23)."""
    import cv2

    half = _weight(person[0::2, 0::2], band_px / 2, _EDGE_SIGMA_PX / 2)
    size = (person.shape[1], person.shape[0])
    return cv2.resize(half, size, interpolation=cv2.INTER_LINEAR), half


def _toward(top: np.ndarray, blurred: np.ndarray, weight: np.ndarray) -> None:
    """`top` (uint8, in place) moved toward `blurred` by `weight`, rounded: rint(a + w (b -
    a)) in float32, computed only where the weight is not 0 (compiled,
    `uma.mbc.layered_kernels.blend`, the same operations as the numpy form)."""
    from uma.mbc.layered_kernels import blend

    blend(top, blurred, weight)
