"""Scoring what the receiver displays against the source frame it should show.

Units: PSNR in dB, SSIM unitless in [-1, 1]. Scores are on luma at the source's resolution: a
picture decoded at a lower rung is upscaled first (bilinear), as a receiver's display would.
Before the first picture arrives the display is mid-grey.
"""

from __future__ import annotations

import time

import numpy as np

from uma.config.scenario import MetricsConfig

__all__ = ["QualityMeter"]


class QualityMeter:
    """Computes PSNR and SSIM per displayed frame; caches the upscaled luma of the shown picture."""

    def __init__(self, config: MetricsConfig, *, width: int, height: int, account: bool = False):
        self.config = config
        self.width = width
        self.height = height
        self._cached_index = None
        self._cached_luma = None
        self.account = account
        self.seconds = 0.0
        self.pairs: list[tuple[int, int]] = []  # (source frame, shown frame) for the benchmark

    def shown_luma(self, shown: int, picture: np.ndarray | None) -> np.ndarray:
        if picture is None:
            return np.full((self.height, self.width), 128, dtype=np.uint8)
        if shown == self._cached_index:
            return self._cached_luma
        import cv2

        luma = picture[: picture.shape[0] * 2 // 3]
        if luma.shape != (self.height, self.width):
            luma = cv2.resize(luma, (self.width, self.height), interpolation=cv2.INTER_LINEAR)
        self._cached_index, self._cached_luma = shown, luma
        return luma

    def score(
        self, source: np.ndarray, shown: int, picture: np.ndarray | None
    ) -> tuple[float, float]:
        start = time.perf_counter() if self.account else 0.0
        from uma.metrics.quality import psnr_db, ssim

        reference = source[: self.height]
        test = self.shown_luma(shown, picture)
        psnr = psnr_db(reference, test) if self.config.psnr else float("nan")
        similarity = ssim(reference, test) if self.config.ssim else float("nan")
        if self.account:
            self.seconds += time.perf_counter() - start
        return psnr, similarity
