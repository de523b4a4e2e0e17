"""Helpers the VP8 and AV1 tests share: frames, the steady rate, the mean PSNR of a round trip."""

import numpy as np

from uma.metrics.quality import psnr_db
from uma.video import PatternSource


def pattern(n, width=176, height=144, seed=2):
    return list(PatternSource(width, height, seed=seed, frame_count=n).frames())


def steady_kbps(sizes_bits, fps):
    """Mean rate after the first second, which carries the opening key frame."""
    skip = int(round(fps))
    return sum(sizes_bits[skip:]) / ((len(sizes_bits) - skip) / fps) / 1000.0


def round_trip_psnr_db(encoder, decoder, frames):
    """Mean luma PSNR of `frames` encoded and decoded in order; every picture has its shape."""
    height = frames[0].shape[0] * 2 // 3
    scores = []
    for frame in frames:
        picture = decoder.decode(encoder.encode(frame).data)
        assert picture.shape == frame.shape and picture.dtype == np.uint8
        scores.append(psnr_db(frame[:height], picture[:height]))
    return float(np.mean(scores))
