"""Scoring what the receiver displays against the source frame it should show.

Units: PSNR in dB, SSIM unitless in [-1, 1]. Scores are on luma at the source's resolution: a
picture decoded at a lower rung is upscaled first (bilinear), as a receiver's display would.
Before the first picture arrives the display is mid-grey. Face-region scores are the same
metrics over the source frame's face box only (`uma.face.region`); NaN without a box.

The frame and its face box are scored in one pass (`uma.metrics.quality.frame_scores`: one
SSIM map for both). OpenCV's filters release the GIL, so scoring can run on a small thread
pool beside the simulation; the scores land in the frame log when `finish()` is called.
Results do not depend on the pool or the batching: each score is a pure function of its two
planes.
"""

from __future__ import annotations

import time
from collections import deque
from concurrent.futures import Future, ThreadPoolExecutor

import numpy as np

from uma.config.scenario import MetricsConfig

__all__ = ["QualityMeter"]

# Instants waiting beyond this many hold their frames in memory; the simulation waits instead.
MAX_PENDING = 64
# Instants handed to a scoring thread at once: each hand-over wakes a thread, which on a busy
# machine takes the core from the simulation's thread for a while; fewer, larger jobs.
BATCH = 8


class QualityMeter:
    """Computes PSNR and SSIM per displayed frame; caches the upscaled luma of the shown picture."""

    def __init__(self, config: MetricsConfig, *, width: int, height: int):
        self.config = config
        self.width = width
        self.height = height
        self._cached_index = None
        self._cached_luma = None
        self.seconds = 0.0  # wall time inside scoring calls, summed over threads
        self._pool = ThreadPoolExecutor(config.workers) if config.workers > 0 else None
        self._batch: list[tuple] = []  # instants to score, handed to a thread BATCH at a time
        self._pending: deque[tuple[int, Future]] = deque()  # (instants, their batch's job)
        self.results: dict[int, tuple[float, float, float, float]] = {}

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

    def _score(self, reference: np.ndarray, test: np.ndarray, box) -> tuple[float, ...]:
        from uma.metrics.quality import frame_scores

        start = time.perf_counter()
        scores = frame_scores(
            reference, test, box, with_psnr=self.config.psnr, with_ssim=self.config.ssim
        )
        return (*scores, time.perf_counter() - start)

    def submit(
        self,
        index: int,
        source: np.ndarray,
        shown: int,
        picture: np.ndarray | None,
        *,
        box=None,
    ) -> None:
        """Score display instant `index`: `source` frame against the `shown` picture, whole and
        over the face `box` (a `uma.face.Box` of the source frame, or None)."""
        reference = source[: self.height]
        test = self.shown_luma(shown, picture)
        if self._pool is None:
            *scores, spent = self._score(reference, test, box)
            self.seconds += spent
            self.results[index] = tuple(scores)
            return
        self._batch.append((index, reference, test, box))
        if len(self._batch) >= BATCH:
            self._submit_batch()

    def _score_batch(self, batch: list) -> list[tuple]:
        return [(index, self._score(ref, test, box)) for index, ref, test, box in batch]

    def _submit_batch(self) -> None:
        batch, self._batch = self._batch, []
        self._pending.append((len(batch), self._pool.submit(self._score_batch, batch)))
        waiting = sum(count for count, _ in self._pending)
        while waiting > MAX_PENDING or (self._pending and self._pending[0][1].done()):
            waiting -= self._collect_one()

    def _collect_one(self) -> int:
        count, future = self._pending.popleft()
        for index, (*scores, spent) in future.result():
            self.seconds += spent
            self.results[index] = tuple(scores)
        return count

    def finish(self) -> dict[int, tuple[float, float, float, float]]:
        """Wait for every score; returns {instant: (psnr_db, ssim, psnr_face_db, ssim_face)}."""
        if self._batch:
            self._submit_batch()
        while self._pending:
            self._collect_one()
        if self._pool is not None:
            self._pool.shutdown()
        return self.results
