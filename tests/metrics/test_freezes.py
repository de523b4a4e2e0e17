"""WebRTC's freeze statistics on hand-made display timelines (W3C webrtc-stats definition)."""

import numpy as np
import pytest

from uma.metrics.freezes import freeze_stats, rendered_instants_ms


def timeline(render_times_ms, *, tick_ms=None):
    """Display ticks showing a new frame at each of `render_times_ms` (and repeats between)."""
    render_times_ms = np.asarray(render_times_ms, dtype=float)
    if tick_ms is None:
        return render_times_ms, np.arange(render_times_ms.size)
    ticks = np.arange(0.0, render_times_ms[-1] + tick_ms / 2, tick_ms)
    shown = np.searchsorted(render_times_ms, ticks, side="right") - 1
    return ticks, shown


def intervals_to_times(intervals_ms):
    return np.concatenate(([0.0], np.cumsum(intervals_ms)))


def test_gap_at_the_threshold_at_25_fps():
    # 29 intervals of 40 ms and one of 200: average 45.33 ms, threshold max(136, 195.3) ms.
    display, shown = timeline(intervals_to_times([40.0] * 29 + [200.0]))
    stats = freeze_stats(display, shown, duration_s=1.36)
    assert stats["freeze_count"] == 1
    assert stats["total_freezes_duration_s"] == pytest.approx(0.2)
    # 160 ms: average 44 ms, threshold 194 ms: no freeze.
    display, shown = timeline(intervals_to_times([40.0] * 29 + [160.0]))
    assert freeze_stats(display, shown, duration_s=1.32)["freeze_count"] == 0


def test_at_5_fps_three_average_frames_rule():
    # 200 ms frames: a 600 ms gap is below max(3 x 213.3, 363.3) = 640 ms; 700 ms is above 650.
    display, shown = timeline(intervals_to_times([200.0] * 29 + [600.0]))
    assert freeze_stats(display, shown, duration_s=6.4)["freeze_count"] == 0
    display, shown = timeline(intervals_to_times([200.0] * 29 + [700.0]))
    stats = freeze_stats(display, shown, duration_s=6.5)
    assert stats["freeze_count"] == 1
    assert stats["total_freezes_duration_s"] == pytest.approx(0.7)


def test_repeated_frames_are_not_renders_and_count_two_freezes():
    renders = intervals_to_times([40.0] * 40 + [400.0] + [40.0] * 40 + [1000.0] + [40.0] * 10)
    display, shown = timeline(renders, tick_ms=40.0)
    assert np.allclose(rendered_instants_ms(display, shown), renders)
    stats = freeze_stats(display, shown, duration_s=5.0)
    assert stats["freeze_count"] == 2
    assert stats["total_freezes_duration_s"] == pytest.approx(1.4)
    assert stats["displayed_fps"] == pytest.approx(renders.size / 5.0)


def test_nothing_shown_yet_and_too_few_intervals():
    display = np.arange(10) * 40.0
    shown = np.array([-1, -1, 0, 0, 1, 2, 2, 2, 2, 2])
    stats = freeze_stats(display, shown, duration_s=0.4)
    assert stats["freeze_count"] == 0  # two intervals only: no freeze is called before five
    assert stats["displayed_fps"] == pytest.approx(3 / 0.4)
    # The stalled tail after the last render is not a freeze (no frame ends it).
    display, shown = timeline(intervals_to_times([40.0] * 10), tick_ms=40.0)
    display = np.concatenate((display, display[-1] + 40.0 * np.arange(1, 50)))
    shown = np.concatenate((shown, np.full(49, shown[-1])))
    assert freeze_stats(display, shown, duration_s=2.4)["freeze_count"] == 0
