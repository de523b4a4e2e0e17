"""Capture-to-display delay, counted as Salsify (NSDI 2018) does.

Units: milliseconds. A frame that is never displayed counts as arriving with the next frame that
is; so a freeze shows up as delay, and a lower frame rate as a little delay too. Frames after the
last displayed one count as displayed at the last display instant (a lower bound).
"""

from __future__ import annotations

import numpy as np

__all__ = ["display_delays_ms"]


def display_delays_ms(
    capture_ms: np.ndarray, display_ms: np.ndarray, shown_frame: np.ndarray
) -> np.ndarray:
    """Per source frame, the time from its capture to the first display of it or a newer frame.

    `display_ms[k]` is the k-th display instant and `shown_frame[k]` the frame shown then (-1 for
    nothing); shown frames never go back in time.
    """
    frames = capture_ms.shape[0]
    first_shown = np.full(frames, np.inf)
    valid = shown_frame >= 0
    # Ticks are in time order, so the first tick showing frame j is its first display.
    for tick in np.flatnonzero(valid)[::-1]:
        first_shown[shown_frame[tick]] = display_ms[tick]
    next_display = np.minimum.accumulate(first_shown[::-1])[::-1]
    if frames and np.isinf(next_display).any():
        last = np.nanmax(display_ms) if np.isfinite(display_ms).any() else 0.0
        next_display = np.where(np.isinf(next_display), last, next_display)
    return next_display - capture_ms
