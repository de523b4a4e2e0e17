"""Resizing of YUV 4:2:0 frames, plane by plane (for rung changes of resolution).

Frames are arrays of shape (H * 3 // 2, W), uint8; sizes in pixels, even. Area averaging when
shrinking (no aliasing), bilinear when enlarging; OpenCV, about 0.1 ms for CIF to QCIF.
"""

from __future__ import annotations

import numpy as np

from uma.errors import VideoError

__all__ = ["resize_yuv420", "split_planes"]


def split_planes(frame: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Views of the Y, U and V planes of a (H * 3 // 2, W) frame."""
    if frame.ndim != 2 or frame.shape[0] % 3 or frame.shape[1] % 2:
        raise VideoError(f"expected a YUV 4:2:0 frame of shape (H * 3 // 2, W), got {frame.shape}")
    height = frame.shape[0] * 2 // 3
    width = frame.shape[1]
    y = frame[:height]
    chroma = frame[height:].reshape(2, height // 2, width // 2)
    return y, chroma[0], chroma[1]


def resize_yuv420(frame: np.ndarray, width: int, height: int) -> np.ndarray:
    """`frame` resized to `width` x `height`: area averaging down, bilinear up.

    Returns `frame` itself when it already has that size.
    """
    import cv2

    if width < 2 or height < 2 or width % 2 or height % 2:
        raise VideoError(f"resize: expected an even positive size, got {width}x{height}")
    y, u, v = split_planes(frame)
    if (y.shape[1], y.shape[0]) == (width, height):
        return frame
    shrinking = width * height < y.shape[0] * y.shape[1]
    interpolation = cv2.INTER_AREA if shrinking else cv2.INTER_LINEAR
    out = np.empty((height * 3 // 2, width), dtype=np.uint8)
    out[:height] = cv2.resize(y, (width, height), interpolation=interpolation)
    chroma = out[height:].reshape(2, height // 2, width // 2)
    chroma[0] = cv2.resize(u, (width // 2, height // 2), interpolation=interpolation)
    chroma[1] = cv2.resize(v, (width // 2, height // 2), interpolation=interpolation)
    return out
