"""The estimator's delay trend on scripted reports: a queue that builds, a steady one, growth."""

import pytest

from uma.config import EstimatorConfig
from uma.engine.estimator import delay_trend_ms_per_s, initial_estimate, update_estimate
from uma.engine.reports import ReceiverReport

TREND = EstimatorConfig(initial_kbps=500.0, trend_window_s=1.0, increase_cap=1.5)


def replace(config, **changes):
    return config.model_copy(update=changes)


def _report(t_s, kbps, queue_ms):
    return ReceiverReport(
        sent_s=t_s,
        interval_s=0.1,
        received_bits=int(kbps * 100),
        packets_received=5,
        packets_lost=0,
        highest_seq=100,
        queue_delay_ms=queue_ms,
    )


def _feed(config, queue_ms_at, *, kbps=400.0, reports=10):
    state = initial_estimate(config)
    for i in range(reports):
        t_s = 0.1 * (i + 1)
        state = update_estimate(
            state, _report(t_s, kbps, queue_ms_at(t_s)), now_s=t_s, outstanding_bits=0,
            config=config,
        )  # fmt: skip
    return state


def test_slope_of_scripted_delays():
    assert delay_trend_ms_per_s(((0.0, 0.0), (0.1, 10.0), (0.2, 20.0))) == pytest.approx(100.0)
    assert delay_trend_ms_per_s(((0.0, 5.0), (0.1, 5.0))) == 0.0


def test_a_queue_that_builds_is_backed_off_before_it_stands():
    building = _feed(TREND, lambda t: 100.0 * t)  # 100 ms/s, still below queue_high_ms
    assert building.trend_ms_per_s == pytest.approx(100.0)
    assert building.estimate_kbps < 400.0
    # Without the trend the same reports never cut: the queue stays under queue_high_ms.
    blind = _feed(replace(TREND, trend_window_s=0.0, increase_cap=3.0), lambda t: 100.0 * t)
    assert blind.estimate_kbps >= 500.0


def test_a_steady_small_queue_lets_it_grow_but_only_to_what_it_measures():
    steady = _feed(TREND, lambda t: 5.0, kbps=400.0, reports=40)
    assert steady.estimate_kbps == pytest.approx(1.5 * 400.0)
    loose = _feed(replace(TREND, increase_cap=3.0), lambda t: 5.0, kbps=400.0, reports=40)
    assert loose.estimate_kbps > steady.estimate_kbps


def test_rising_delay_holds_growth():
    rising = _feed(replace(TREND, trend_high_ms_per_s=500.0), lambda t: 20.0 * t, reports=10)
    # Two reports grow it before a trend can be measured (three samples); then it holds.
    assert rising.estimate_kbps == pytest.approx(500.0 * 1.05**2)
