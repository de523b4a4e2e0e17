"""GCC's detector against hand-worked cases: groups, trendline, adaptive threshold, over-use."""

from __future__ import annotations

import pytest

from uma.control.gcc_delay import (
    AdaptiveThreshold,
    GroupDelta,
    InterArrival,
    OveruseDetector,
    Trendline,
    Usage,
    least_squares_slope,
)


def test_packets_sent_within_5_ms_are_one_group():
    groups = InterArrival()
    assert groups.on_packet(0.0, 20.0) is None
    assert groups.on_packet(4.0, 25.0) is None  # same group
    assert groups.on_packet(40.0, 61.0) is None  # second group starts; first has no previous
    delta = groups.on_packet(80.0, 105.0)  # third starts: the second completes
    assert delta == GroupDelta(send_delta_ms=36.0, arrival_delta_ms=36.0, arrival_ms=61.0)


def test_a_burst_that_catches_up_joins_the_group_until_100_ms():
    groups = InterArrival()
    groups.on_packet(0.0, 100.0)
    # sent 20 ms later but arrived 1 ms later: queued behind, released in one burst
    assert groups._belongs(groups._current, 20.0, 101.0)
    # the same, but the group would span more than 100 ms of arrivals
    groups._current.first_arrival_ms = 0.0
    assert not groups._belongs(groups._current, 20.0, 101.0)


def test_least_squares_slope():
    assert least_squares_slope([(0, 1), (1, 3), (2, 5)]) == pytest.approx(2.0)
    assert least_squares_slope([(1, 1), (1, 5)]) == 0.0


def test_trendline_of_a_steadily_growing_queue():
    # every group arrives 1 ms later than it was sent after the one before: the delay grows
    # 1 ms per 40 ms. After smoothing the slope settles towards 1/40.
    trend = Trendline(window=20)
    out = 0.0
    for k in range(200):
        out = trend.update(GroupDelta(40.0, 41.0, 41.0 * k))
    assert trend.trend == pytest.approx(1 / 41, rel=0.02)
    assert out == pytest.approx(60 * 4.0 * trend.trend)  # min(deltas, 60) x gain


def test_threshold_moves_up_with_k_up_and_down_with_k_down():
    up = AdaptiveThreshold()
    up.update(20.0, 0.0)  # the first call starts the clock
    assert up.update(20.0, 100.0) == pytest.approx(12.5 + 0.0087 * (20.0 - 12.5) * 100.0)
    down = AdaptiveThreshold()
    down.update(10.0, 0.0)
    assert down.update(10.0, 50.0) == pytest.approx(12.5 + 0.039 * (10.0 - 12.5) * 50.0)


def test_threshold_ignores_spikes_caps_the_step_and_stays_in_bounds():
    gamma = AdaptiveThreshold()
    gamma.update(0.0, 0.0)
    assert gamma.update(30.0, 10.0) == 12.5  # |m| > gamma + 15: no update
    assert gamma.update(13.5, 1010.0) == pytest.approx(12.5 + 0.0087 * 1.0 * 100.0)  # dt capped
    low = AdaptiveThreshold()
    low.update(0.0, 0.0)
    assert low.update(0.0, 100.0) == 6.0  # 12.5 - 0.039 x 12.5 x 100 < 6


def test_overuse_needs_10_ms_over_two_groups_with_the_trend_not_falling():
    detector = OveruseDetector()
    assert detector.detect(20.0, 10.0, 0.0) is Usage.NORMAL  # 5 ms over, one group
    assert detector.detect(20.0, 10.0, 10.0) is Usage.OVER  # 15 ms over, two groups


def test_no_overuse_while_the_trend_falls():
    detector = OveruseDetector()
    detector.detect(20.0, 10.0, 0.0)
    assert detector.detect(19.0, 10.0, 10.0) is Usage.NORMAL


def test_underuse_and_normal():
    detector = OveruseDetector()
    assert detector.detect(-20.0, 10.0, 0.0) is Usage.UNDER
    assert detector.detect(1.0, 10.0, 10.0) is Usage.NORMAL
