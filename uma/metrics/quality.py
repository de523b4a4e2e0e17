"""Picture quality of a displayed frame against its source: PSNR and SSIM of 8-bit planes.

Pass luma planes (`frame[:H]` of a YUV 4:2:0 frame), as is usual for video quality. Units: PSNR
in dB for a peak of 255, capped at `PSNR_CAP_DB` (100 dB) for identical pictures so a mean stays
finite; SSIM unitless in [-1, 1]; `ssim_db` = -10 log10(1 - SSIM), the form real-time video work
reports (Salsify), capped at `SSIM_DB_CAP` (100 dB).

SSIM is scikit-image's `structural_similarity` with its defaults (7x7 uniform window, K1 0.01,
K2 0.03, sample covariance), data range 255, on float32 planes: float32 input keeps scikit-image
in float32 and costs about half of uint8 input, which it converts to float64; the result agrees
to 1e-5. SSIM dominates a simulation's cost. Measured on this 2-core machine, one CIF luma
plane (akiyo coded at 256 kbit/s), medians: 8.4-9.0 ms on uint8, 4.5-5.0 ms on float32 (this
function), 0.6 ms with `scale=2`; QCIF: 0.67, 0.57 and 0.19 ms; PSNR 0.07 ms at CIF.

Much of the full-size cost is not arithmetic but page faults: glibc serves each CIF-sized
temporary (> 128 KiB) with a fresh mmap, whose pages the kernel must zero on first touch.
`keep_freed_memory()` (once per process) makes glibc reuse its heap instead: CIF SSIM then
costs 2.1-2.3 ms on float32 and 2.8-3.2 ms on uint8 (same values, bit for bit). Without it the
cost varies 2.1-5.1 ms from process to process, with the heap's history.

`scale=2` averages 2x2 blocks of both planes first (a quarter of the pixels, ~8x cheaper at CIF
as the planes then fit in cache). It hides coding artefacts smaller than the blocks and reads
higher: akiyo CIF, mean of 60 frames, full size against scale 2: 0.908 / 0.949 at 64 kbit/s,
0.946 / 0.975 at 128, 0.975 / 0.990 at 256, 0.9941 / 0.9983 at 768, i.e. +2.6 to +5.4 dB in
`ssim_db`. Rankings hold but values do not compare with published full-size SSIM; compare
only values computed at the same scale. (Wang et al.'s own recipe downsamples by
round(min(H, W) / 256), which is 1, no downsampling, for CIF and QCIF.)
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "psnr_db",
    "ssim",
    "ssim_db",
    "region_scores",
    "keep_freed_memory",
    "PSNR_CAP_DB",
    "SSIM_DB_CAP",
]

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


def region_scores(
    reference: np.ndarray, test: np.ndarray, box, *, with_psnr: bool = True, with_ssim: bool = True
) -> tuple[float, float]:
    """(PSNR dB, SSIM) of two planes over `box` only (x, y, width, height, clipped to the plane).

    NaN for a metric switched off, without a box, and SSIM NaN for a box under 7x7 pixels.
    """
    nan = float("nan")
    if box is None:
        return nan, nan
    _same_shape(reference, test, "face-region scores")
    x0, y0 = max(0, int(box.x)), max(0, int(box.y))
    x1 = min(reference.shape[1], int(box.x) + int(box.width))
    y1 = min(reference.shape[0], int(box.y) + int(box.height))
    if x1 <= x0 or y1 <= y0:
        return nan, nan
    ref, tst = reference[y0:y1, x0:x1], test[y0:y1, x0:x1]
    face_psnr = psnr_db(ref, tst) if with_psnr else nan
    face_ssim = ssim(ref, tst) if with_ssim and min(ref.shape) >= 7 else nan
    return face_psnr, face_ssim


def ssim_db(similarity: float) -> float:
    """SSIM in dB, -10 log10(1 - SSIM), capped at `SSIM_DB_CAP`; NaN stays NaN."""
    if math.isnan(similarity):
        return math.nan
    if similarity >= 1.0 - 10 ** (-SSIM_DB_CAP / 10):
        return SSIM_DB_CAP
    return -10.0 * math.log10(1.0 - similarity)


def keep_freed_memory(*, mmap_threshold_bytes: int = 64 << 20, trim_bytes: int = 256 << 20) -> bool:
    """Make glibc's malloc keep and reuse freed memory for large arrays, for this whole process.

    Sets M_MMAP_THRESHOLD (allocations below it come from the heap, not a fresh mmap) and
    M_TRIM_THRESHOLD (free memory kept at the heap's top before it is returned to the system).
    Call once at the start of a run or benchmark; it changes speed, never results. The heap
    may then hold up to `trim_bytes` more than it uses. Returns False where the C library is
    not glibc (nothing is changed).
    """
    import ctypes
    import ctypes.util

    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    m_trim_threshold, m_mmap_threshold = -1, -3  # from glibc's malloc.h
    return bool(mallopt(m_mmap_threshold, mmap_threshold_bytes)) and bool(
        mallopt(m_trim_threshold, trim_bytes)
    )
