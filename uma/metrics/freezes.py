"""WebRTC's freeze statistics of a display timeline, as the W3C webrtc-stats define them.

Units: display instants in ms in, durations in seconds out (as the stats are).

A frame is *rendered* at the first display instant that shows it. A freeze is an interval
between two consecutively rendered frames that is at least max(3 x the average frame
duration, the average + 150 ms), the average being the linear mean of the last 30 intervals,
this one included; as in libwebrtc's VideoQualityObserver, no freeze is called before 5
intervals have been seen. `freeze_count` counts them and `total_freezes_duration_s` sums their
whole intervals. The stalled tail after the last rendered frame is no freeze by this definition
(no frame ends it); `freeze_ratio` counts it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["freeze_stats", "rendered_instants_ms", "AVERAGE_FRAMES", "MIN_INCREASE_MS"]

AVERAGE_FRAMES = 30
MIN_INCREASE_MS = 150.0
MIN_INTERVALS = 5


def rendered_instants_ms(display_ms: np.ndarray, shown_frame: np.ndarray) -> np.ndarray:
    """The display instants at which a frame not shown before appears."""
    shown = np.asarray(shown_frame)
    times = np.asarray(display_ms, dtype=float)
    previous = np.concatenate(([-1], shown[:-1])) if shown.size else shown
    new = (shown >= 0) & (shown != previous)
    return times[new]


def freeze_stats(
    display_ms: np.ndarray, shown_frame: np.ndarray, *, duration_s: float
) -> dict[str, Any]:
    """`freeze_count`, `total_freezes_duration_s` and `displayed_fps` of one display timeline."""
    rendered = rendered_instants_ms(display_ms, shown_frame)
    intervals = np.diff(rendered)
    count = 0
    total_ms = 0.0
    for index, interval in enumerate(intervals):
        if index + 1 < MIN_INTERVALS:
            continue
        recent = intervals[max(0, index + 1 - AVERAGE_FRAMES) : index + 1]
        average = float(recent.mean())
        if interval >= max(3.0 * average, average + MIN_INCREASE_MS):
            count += 1
            total_ms += float(interval)
    return {
        "freeze_count": count,
        "total_freezes_duration_s": round(total_ms / 1000.0, 3),
        "displayed_fps": round(rendered.size / duration_s, 3) if duration_s > 0 else None,
    }
