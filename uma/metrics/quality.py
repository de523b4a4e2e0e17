"""Picture quality of a displayed frame against its source: PSNR and SSIM on luma.

Units: PSNR in dB (capped at 100 dB for identical pictures, never infinite), SSIM unitless.
SSIM is scikit-image's `structural_similarity` (7x7 uniform window, data range 255), given
float32 planes: about twice as fast as uint8 input here, same result to 1e-6.
"""

from __future__ import annotations

import numpy as np

__all__ = ["psnr_db", "ssim", "PSNR_CAP_DB"]

PSNR_CAP_DB = 100.0


def psnr_db(reference: np.ndarray, test: np.ndarray) -> float:
    """Peak signal-to-noise ratio of 8-bit planes, in dB."""
    if reference.shape != test.shape:
        raise ValueError(f"PSNR of different shapes {reference.shape} and {test.shape}")
    diff = reference.astype(np.float32) - test.astype(np.float32)
    mse = float(np.mean(diff * diff))
    if mse <= 255.0**2 * 10 ** (-PSNR_CAP_DB / 10):
        return PSNR_CAP_DB
    return float(10.0 * np.log10(255.0**2 / mse))


def ssim(reference: np.ndarray, test: np.ndarray) -> float:
    """Structural similarity of 8-bit planes (scikit-image, data range 255)."""
    from skimage.metrics import structural_similarity

    if reference.shape != test.shape:
        raise ValueError(f"SSIM of different shapes {reference.shape} and {test.shape}")
    return float(
        structural_similarity(
            reference.astype(np.float32), test.astype(np.float32), data_range=255.0
        )
    )
