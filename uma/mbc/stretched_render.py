"""The stretched scene (a renderer that is not layered): the whole reference warped by the
scene mesh, luma and chroma alike.

Units: pixels; pictures planar YUV 4:2:0 (H * 3 // 2, W) uint8.
"""

from __future__ import annotations

import numpy as np

__all__ = ["stretched"]


def stretched(reference: np.ndarray, chroma_planes, map_x: np.ndarray, map_y: np.ndarray):
    """`reference` (YUV 4:2:0) stretched by a scene mesh's per-pixel maps `map_x`, `map_y`
    (luma coordinates; `uma.mbc.scene_render.SceneRenderer.maps`), its chroma from
    `chroma_planes` (U, V) at each 2x2 block's mean position."""
    import cv2

    height, width = map_x.shape
    out = np.empty((height * 3 // 2, width), dtype=np.uint8)
    out[:height] = cv2.remap(
        reference[:height], map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
    )
    # Chroma: each 2x2 block's mean position, in chroma-plane coordinates.
    cx = (map_x[0::2, 0::2] + map_x[1::2, 1::2] - 1.0) * 0.25
    cy = (map_y[0::2, 0::2] + map_y[1::2, 1::2] - 1.0) * 0.25
    chroma = out[height:].reshape(2, height // 2, width // 2)
    for plane, source in zip(chroma, chroma_planes, strict=True):
        plane[:] = cv2.remap(source, cx, cy, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return out
