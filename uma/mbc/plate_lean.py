"""What the plate shows where it never saw the background: the fill, leaned toward the person.

Units: pixels; planes (H, W) uint8. The plate's fill (`uma.mbc.layers.fill_unknown`) averages
the background around the person; where the moving person uncovers a spot the plate never saw,
the truth is often darker or lighter than that average (a seat's shadow beside a head, a neck
beside a jaw). The newest reference, blurred, says roughly how dark it was there; the fill
leans part of the way toward it (measured and chosen in docs/mbc.md, session mbc19). The blur
keeps the old person's outline from showing as a second head.
"""

from __future__ import annotations

import numpy as np

__all__ = ["REFERENCE_OF_FILL", "REFERENCE_BLUR_PX", "lean_on_reference"]

# The never-seen luma: this share of the newest reference blurred (sigma, px), the rest the
# fill (chosen on the bench's frames 0-149, checked on 150-299: docs/mbc.md, session mbc19).
REFERENCE_OF_FILL = 0.25
REFERENCE_BLUR_PX = 4.0


def lean_on_reference(filled: np.ndarray, reference: np.ndarray, known: np.ndarray) -> None:
    """`filled`'s pixels not `known` moved, in place, `REFERENCE_OF_FILL` of the way toward
    `reference` blurred over `REFERENCE_BLUR_PX` (the fill alone averages what lies around);
    blurred over the unknown pixels' box and the blur's reach only (the same values)."""
    import cv2

    x, y, w, h = cv2.boundingRect((~known).view(np.uint8))
    if REFERENCE_OF_FILL <= 0.0 or w == 0:
        return
    reach = int(np.ceil(4 * REFERENCE_BLUR_PX))  # OpenCV's uint8 kernel reaches 3 sigma
    y0, x0 = max(y - reach, 0), max(x - reach, 0)
    crop = reference[y0 : y + h + reach, x0 : x + w + reach]
    blurred = cv2.GaussianBlur(crop, (0, 0), REFERENCE_BLUR_PX)[
        y - y0 : y - y0 + h, x - x0 : x - x0 + w
    ]
    box, unknown = filled[y : y + h, x : x + w], ~known[y : y + h, x : x + w]
    mixed = (1.0 - REFERENCE_OF_FILL) * box[unknown] + REFERENCE_OF_FILL * blurred[unknown]
    box[unknown] = np.rint(mixed).astype(np.uint8)
