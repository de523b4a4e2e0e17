import pytest

from uma.config import EstimatorConfig
from uma.engine.estimator import initial_estimate, update_estimate
from uma.engine.reports import ReceiverReport

CONFIG = EstimatorConfig(initial_kbps=500.0, queue_high_ms=150.0, queue_low_ms=40.0)


def report(kbps, *, queue_ms=10.0, lost=0, received=10, interval_s=0.1):
    return ReceiverReport(
        sent_s=1.0,
        interval_s=interval_s,
        received_bits=int(kbps * 1000 * interval_s),
        packets_received=received,
        packets_lost=lost,
        highest_seq=100,
        queue_delay_ms=queue_ms if received else None,
    )


def test_growing_queue_cuts_to_received_rate():
    state = update_estimate(
        initial_estimate(CONFIG),
        report(200, queue_ms=400),
        now_s=1.0,
        outstanding_bits=0,
        config=CONFIG,
    )
    assert state.estimate_kbps == pytest.approx(200 * CONFIG.decrease_factor)


def test_decrease_at_most_once_per_drain_time():
    state = update_estimate(
        initial_estimate(CONFIG),
        report(200, queue_ms=400),
        now_s=1.0,
        outstanding_bits=0,
        config=CONFIG,
    )
    again = update_estimate(
        state, report(150, queue_ms=400), now_s=1.1, outstanding_bits=0, config=CONFIG
    )
    assert again.estimate_kbps == state.estimate_kbps
    later = update_estimate(
        state, report(150, queue_ms=400), now_s=2.1, outstanding_bits=0, config=CONFIG
    )
    assert later.estimate_kbps < state.estimate_kbps


def test_heavy_loss_cuts_estimate():
    state = update_estimate(
        initial_estimate(CONFIG), report(300, lost=5), now_s=1.0, outstanding_bits=0, config=CONFIG
    )
    assert state.estimate_kbps < 300


def test_empty_queue_grows_but_stays_anchored():
    state = initial_estimate(CONFIG)
    for step in range(100):
        state = update_estimate(
            state, report(400, queue_ms=5), now_s=step * 0.1, outstanding_bits=0, config=CONFIG
        )
    assert 500 < state.estimate_kbps <= 3 * 400 + 1e-9


def test_silence_with_data_in_flight_decays_to_floor():
    state = initial_estimate(CONFIG)
    for step in range(600):
        state = update_estimate(
            state, report(0, received=0), now_s=step * 0.1, outstanding_bits=10_000, config=CONFIG
        )
    assert state.estimate_kbps == pytest.approx(CONFIG.min_kbps)


def test_silence_without_data_keeps_estimate():
    state = update_estimate(
        initial_estimate(CONFIG),
        report(0, received=0),
        now_s=1.0,
        outstanding_bits=0,
        config=CONFIG,
    )
    assert state.estimate_kbps == CONFIG.initial_kbps


def test_a_collapse_is_followed_each_window_not_each_drain_time():
    """A handover to a slow link: 500 kbit/s arriving, then 40 with the queue 5 s deep. Waiting
    5 s between decreases would keep sending far above what arrives; below `collapse_below` of
    the estimate the estimator cuts once per window instead."""

    def run(config):
        state = initial_estimate(config)
        for step in range(40):
            kbps, queue_ms = (500, 10.0) if step < 10 else (40, 5000.0)
            state = update_estimate(
                state,
                report(kbps, queue_ms=queue_ms),
                now_s=0.1 * (step + 1),
                outstanding_bits=1,
                config=config,
            )
        return state.estimate_kbps

    assert run(CONFIG) == pytest.approx(40 * CONFIG.decrease_factor, rel=0.01)
    # Off: the first decrease is from a window still full of the old rate, then 5 s of hold.
    assert run(CONFIG.model_copy(update={"collapse_below": 0.0})) > 300.0
