"""Where the block map (`uma.mbc.block_map`) looks: its window of blocks about the drawn face,
and the box of the picture its choice reads.

Units: pixels; blocks of `BLOCK_PX` a side; windows (b0, a0, b1, a1) in blocks (columns b,
rows a).
"""

from __future__ import annotations

import numpy as np

__all__ = ["BLOCK_PX", "WINDOW_BLOCKS", "BLUR_MARGIN_PX", "window_about", "margin_box",
           "window_crop"]  # fmt: skip

BLOCK_PX = 8
WINDOW_BLOCKS = 16  # a side: 128 px at CIF, the head and the outline about it
BLUR_MARGIN_PX = 8  # the blur reads this far outside the window


def window_about(face: np.ndarray, grid: tuple[int, int]):
    """(the window (b0, a0, b1, a1) in blocks about the drawn `face`, the face's centre (x, y
    px)) on a grid of `grid` (rows, cols) blocks; None without a face."""
    import cv2

    x, y, w, h = cv2.boundingRect(face.view(np.uint8))
    if w == 0 or h == 0:
        return None
    rows, cols = grid
    side_r, side_c = min(WINDOW_BLOCKS, rows), min(WINDOW_BLOCKS, cols)
    c0 = int(round((x + w / 2) / BLOCK_PX - side_c / 2))
    r0 = int(round((y + h / 2) / BLOCK_PX - side_r / 2))
    c0, r0 = min(max(c0, 0), cols - side_c), min(max(r0, 0), rows - side_r)
    return (c0, r0, c0 + side_c, r0 + side_r), (x + w / 2, y + h / 2)


def margin_box(window, size) -> tuple[tuple, tuple]:
    """The window's pixel box (y0, x0, y1, x1) and the box a blur of it reads."""
    width, height = size
    c0, r0, c1, r1 = window
    y0, x0, y1, x1 = r0 * BLOCK_PX, c0 * BLOCK_PX, r1 * BLOCK_PX, c1 * BLOCK_PX
    m = BLUR_MARGIN_PX
    return (y0, x0, y1, x1), (max(y0 - m, 0), max(x0 - m, 0), min(y1 + m, height),
                              min(x1 + m, width))  # fmt: skip


def window_crop(mask: np.ndarray, window) -> np.ndarray:
    """`mask` (H, W) cut to the window's pixels."""
    c0, r0, c1, r1 = window
    return mask[r0 * BLOCK_PX : r1 * BLOCK_PX, c0 * BLOCK_PX : c1 * BLOCK_PX]
