"""Wall-clock timing for the benchmarks (never the simulation): the median of repeated calls.

Units: milliseconds.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

__all__ = ["median_ms"]


def median_ms(fn: Callable[[], object], repeats: int = 30) -> float:
    """The median wall time of `repeats` calls of `fn`, in ms (a median: this machine is noisy)."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times) * 1000.0)
