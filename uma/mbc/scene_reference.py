"""The description's own picture as a reference the receiver can render from.

Units: pixels; pictures planar YUV 4:2:0 (H * 3 // 2, W) uint8.
"""

from __future__ import annotations

import numpy as np

from uma.face.describe import ContentDescription

__all__ = ["description_reference"]


def description_reference(description: ContentDescription, size: tuple[int, int]):
    """The description's picture at the source size `size` (W, H) as YUV 4:2:0, and the pose
    of its model there: the texture pasted where it was cut from, mid-grey around it. Made
    once per description and size (a receiver asks again at every change of face source) and
    kept on the description; each call gets its own copies."""
    cache = description.__dict__.setdefault("_scene_references", {})
    key = tuple(int(v) for v in size)
    if key not in cache:
        cache[key] = _reference(description, key)
    picture, params = cache[key]
    return picture.copy(), params.copy()


def _reference(description: ContentDescription, size: tuple[int, int]):
    """`description_reference`'s picture and pose, made."""
    from uma.face.colour import bgr_to_ycbcr

    width, height = size
    planes = np.full((height, width, 3), 128.0, dtype=np.float32)
    texture = bgr_to_ycbcr(description.texture)
    if description.texture.ndim == 2:
        texture[..., 0] = description.gray  # a gray texture is its own luma
    x0, y0 = (int(round(v)) for v in description.origin_px)
    h = min(texture.shape[0], height - y0)
    w = min(texture.shape[1], width - x0)
    if h > 0 and w > 0 and x0 >= 0 and y0 >= 0:
        planes[y0 : y0 + h, x0 : x0 + w] = texture[:h, :w]
    params = np.asarray(description.params, dtype=np.float64).copy()
    params[:2] += (x0, y0)
    return _i420(planes), params


def _i420(planes: np.ndarray) -> np.ndarray:
    """Full-resolution (H, W, 3) float Y, Cb, Cr to YUV 4:2:0 uint8 (chroma 2x2 averaged)."""
    height, width = planes.shape[:2]
    out = np.empty((height * 3 // 2, width), dtype=np.uint8)
    out[:height] = np.clip(np.rint(planes[..., 0]), 0, 255)
    chroma = planes[..., 1:].reshape(height // 2, 2, width // 2, 2, 2).mean(axis=(1, 3))
    out[height:] = np.clip(np.rint(np.moveaxis(chroma, 2, 0)), 0, 255).reshape(height // 2, width)
    return out
