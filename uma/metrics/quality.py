"""Picture quality of a displayed frame against its source: PSNR and SSIM of 8-bit planes.

Pass luma planes (`frame[:H]` of a YUV 4:2:0 frame), as is usual for video quality. Units: PSNR
in dB for a peak of 255, capped at `PSNR_CAP_DB` (100 dB) for identical pictures so a mean stays
finite; SSIM unitless in [-1, 1]; `ssim_db` = -10 log10(1 - SSIM), the form real-time video work
reports (Salsify), capped at `SSIM_DB_CAP` (100 dB).

SSIM is scikit-image's `structural_similarity` with its defaults (7x7 uniform window, K1 0.01,
K2 0.03, sample covariance), data range 255, on float32 planes: float32 input keeps scikit-image
in float32 and costs about half of uint8 input, which it converts to float64; the result agrees
to 1e-6. SSIM dominates a simulation's cost (measured on this 2-core machine, one CIF luma
plane, akiyo coded at 256 kbit/s: ~4.5-5.5 ms on uint8, ~2.1 ms on float32, ~0.55 ms with
`scale=2`). `scale=2` averages 2x2 blocks of both planes first (a quarter of the pixels): it
hides coding artefacts smaller than the blocks and reads higher (akiyo CIF at 64 / 256 / 1200
kbit/s: 0.881 / 0.972 / 0.9969 at full size against 0.922 / 0.987 / 0.9992 at scale 2, i.e.
+1.8 to +6.5 dB in `ssim_db`), so only compare SSIM values computed at the same scale.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["psnr_db", "ssim", "ssim_db", "PSNR_CAP_DB", "SSIM_DB_CAP"]

PSNR_CAP_DB = 100.0
SSIM_DB_CAP = 100.0


def _same_shape(reference: np.ndarray, test: np.ndarray, what: str) -> None:
    if reference.shape != test.shape:
        raise ValueError(f"{what} of different shapes {reference.shape} and {test.shape}")
    if reference.size == 0:
        raise ValueError(f"{what} of empty planes")


def psnr_db(reference: np.ndarray, test: np.ndarray) -> float:
    """Peak signal-to-noise ratio of two 8-bit planes, 10 log10(255^2 / MSE), in dB."""
    _same_shape(reference, test, "PSNR")
    diff = reference.astype(np.float32) - test.astype(np.float32)
    mse = float(np.mean(diff * diff, dtype=np.float64))
    if mse <= 255.0**2 * 10 ** (-PSNR_CAP_DB / 10):
        return PSNR_CAP_DB
    return float(10.0 * np.log10(255.0**2 / mse))


def _downscale(plane: np.ndarray, scale: int) -> np.ndarray:
    import cv2

    height, width = plane.shape[0] // scale, plane.shape[1] // scale
    cropped = plane[: height * scale, : width * scale]
    # INTER_AREA at an integer factor is the exact mean of each scale x scale block
    return cv2.resize(cropped, (width, height), interpolation=cv2.INTER_AREA)


def ssim(reference: np.ndarray, test: np.ndarray, *, scale: int = 1) -> float:
    """Mean structural similarity of two 8-bit planes (scikit-image, data range 255).

    `scale` > 1 averages `scale` x `scale` blocks of both planes first: about `scale`^2 times
    cheaper, and higher than full-size SSIM (see the module notes). Planes must be at least
    7 x 7 after scaling.
    """
    from skimage.metrics import structural_similarity

    _same_shape(reference, test, "SSIM")
    if int(scale) != scale or scale < 1:
        raise ValueError(f"SSIM scale: expected a positive integer, got {scale!r}")
    ref = reference.astype(np.float32)
    tst = test.astype(np.float32)
    if scale > 1:
        ref, tst = _downscale(ref, int(scale)), _downscale(tst, int(scale))
    if min(ref.shape) < 7:
        raise ValueError(f"SSIM needs planes of at least 7x7, got {ref.shape} at scale {scale}")
    return float(structural_similarity(ref, tst, data_range=255.0))


def ssim_db(similarity: float) -> float:
    """SSIM in dB, -10 log10(1 - SSIM), capped at `SSIM_DB_CAP`; NaN stays NaN."""
    if math.isnan(similarity):
        return math.nan
    if similarity >= 1.0 - 10 ** (-SSIM_DB_CAP / 10):
        return SSIM_DB_CAP
    return -10.0 * math.log10(1.0 - similarity)
