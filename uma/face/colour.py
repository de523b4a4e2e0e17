"""The luma and chroma uma's codecs and metrics see: BT.601 limited range (Y 16-235, Cb/Cr 16-240).

Units: 8-bit levels. PyAV's yuv420p frames, libx264 and the quality metrics all use this range;
`cv2.COLOR_BGR2GRAY` is full range (0-255), which on a face differs by up to 9 levels rms, so
every picture that meets a codec frame goes through here.
"""

from __future__ import annotations

import numpy as np

__all__ = ["bgr_to_luma", "bgr_to_ycbcr", "ycbcr_to_bgr"]

# BT.601 limited range from 8-bit R'G'B' (Rec. ITU-R BT.601, as OpenCV's COLOR_BGR2YUV_I420).
_Y = np.array([0.098, 0.504, 0.257])  # B, G, R
_CB = np.array([0.439, -0.291, -0.148])
_CR = np.array([-0.071, -0.368, 0.439])


def bgr_to_ycbcr(image: np.ndarray) -> np.ndarray:
    """(H, W, 3) BGR uint8 to (H, W, 3) float32 Y, Cb, Cr at full resolution (no subsampling).

    A gray (H, W) picture is taken as full-range gray: R = G = B.
    """
    bgr = np.asarray(image, dtype=np.float32)
    if bgr.ndim == 2:
        bgr = np.repeat(bgr[..., None], 3, axis=2)
    matrix = np.stack([_Y, _CB, _CR]).astype(np.float32)  # (3, 3): rows Y, Cb, Cr
    out = bgr @ matrix.T
    out += np.array([16.0, 128.0, 128.0], dtype=np.float32)
    return out


def bgr_to_luma(image: np.ndarray) -> np.ndarray:
    """(H, W) uint8 limited-range luma of a BGR (or full-range gray) picture."""
    return np.clip(np.rint(bgr_to_ycbcr(image)[..., 0]), 0, 255).astype(np.uint8)


def ycbcr_to_bgr(ycbcr: np.ndarray) -> np.ndarray:
    """Inverse of `bgr_to_ycbcr`: (H, W, 3) Y, Cb, Cr to BGR uint8."""
    matrix = np.stack([_Y, _CB, _CR]).astype(np.float64)
    inverse = np.linalg.inv(matrix).astype(np.float32)
    values = np.asarray(ycbcr, dtype=np.float32) - np.array([16.0, 128.0, 128.0], np.float32)
    return np.clip(np.rint(values @ inverse.T), 0, 255).astype(np.uint8)
