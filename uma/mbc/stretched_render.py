"""The stretched scene (a renderer that is not layered): the whole reference warped by the
scene mesh, luma and chroma alike.

Units: pixels; pictures planar YUV 4:2:0 (H * 3 // 2, W) uint8.
"""

from __future__ import annotations

import numpy as np

__all__ = ["stretched"]


def stretched(renderer, params: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The whole reference of a `uma.mbc.scene_render.SceneRenderer` that is not layered,
    stretched by its scene mesh at `params`, and the mask of the face's own pixels."""
    import cv2

    width, height = renderer.size
    map_x, map_y, face = renderer.maps(params)
    out = np.empty((height * 3 // 2, width), dtype=np.uint8)
    out[:height] = cv2.remap(
        renderer.reference[:height], map_x, map_y, cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_REPLICATE,
    )  # fmt: skip
    # Chroma: each 2x2 block's mean position, in chroma-plane coordinates.
    cx = (map_x[0::2, 0::2] + map_x[1::2, 1::2] - 1.0) * 0.25
    cy = (map_y[0::2, 0::2] + map_y[1::2, 1::2] - 1.0) * 0.25
    chroma = out[height:].reshape(2, height // 2, width // 2)
    for plane, source in zip(chroma, (renderer._u, renderer._v), strict=True):
        plane[:] = cv2.remap(source, cx, cy, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return out, face
