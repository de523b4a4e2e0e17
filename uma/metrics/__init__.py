"""Metrics of a run: picture quality (PSNR, SSIM), delay and freeze accounting, aggregates.

Units are in the names of each module's functions and columns.
"""

from uma.metrics.quality import (
    PSNR_CAP_DB,
    SSIM_DB_CAP,
    frame_scores,
    keep_freed_memory,
    psnr_db,
    region_scores,
    ssim,
    ssim_db,
)

__all__ = [
    "psnr_db",
    "region_scores",
    "frame_scores",
    "ssim",
    "ssim_db",
    "keep_freed_memory",
    "PSNR_CAP_DB",
    "SSIM_DB_CAP",
]
