"""WebRTC's receiver-side estimator (aiortc) in a closed loop over one bottleneck."""

import numpy as np
import pytest

pytest.importorskip("aiortc")

from uma.bench.estimator_loop import closed_loop, step_response  # noqa: E402
from uma.config.scenario import EstimatorConfig  # noqa: E402
from uma.engine.estimator import initial_estimate  # noqa: E402
from uma.engine.reports import ReceiverReport  # noqa: E402
from uma.engine.webrtc import abs_send_time, remb_update  # noqa: E402


def test_abs_send_time_is_24_bit_six_point_eighteen():
    assert abs_send_time(1.0) == 1 << 18
    assert abs_send_time(0.5) == 1 << 17
    assert abs_send_time(64.0) == 0  # wraps every 64 s
    assert abs_send_time(65.0) == 1 << 18


@pytest.mark.parametrize("capacity_kbps", [300.0, 1000.0, 2500.0])
def test_constant_capacity_converges_near_it(capacity_kbps):
    trace = closed_loop(lambda t: capacity_kbps, duration_s=60.0)
    tail = trace.time_s >= 45.0
    rate = float(np.median(trace.rate_kbps[tail]))
    assert 0.75 * capacity_kbps <= rate <= 1.1 * capacity_kbps
    # Near capacity without a standing queue: the delay stays below a quarter second.
    assert trace.delay_s[tail].max() < 0.25


def test_aiortc_unbounded_bursts_are_blind_above_2_mbps():
    # Without libwebrtc's 100 ms bound on bursts the queue grows unseen: this is why
    # RembEstimator swaps in the bounded inter-arrival filter.
    blind = closed_loop(lambda t: 2500.0, duration_s=60.0, max_burst=False)
    assert blind.delay_s[-1] > 2.0
    assert float(np.median(blind.rate_kbps[-250:])) > 1.2 * 2500.0


@pytest.mark.parametrize(("high", "low"), [(1000.0, 300.0), (2000.0, 500.0), (300.0, 100.0)])
def test_step_down_backs_off_within_a_second_and_a_half(high, low):
    result = step_response(high_kbps=high, low_kbps=low)
    assert 0.8 * high <= result["converged_kbps"] <= 1.05 * high
    assert result["backoff_s"] is not None and result["backoff_s"] <= 1.5
    assert 0.6 * low <= result["settled_kbps"] <= 1.1 * low


def test_remb_update_takes_the_remb_and_holds_without_one():
    config = EstimatorConfig()
    state = initial_estimate(config)
    report = ReceiverReport(
        sent_s=1.0,
        interval_s=0.1,
        received_bits=50_000,
        packets_received=5,
        packets_lost=0,
        highest_seq=4,
        queue_delay_ms=3.0,
        remb_kbps=812.5,
    )
    state = remb_update(state, report, now_s=1.0, outstanding_bits=0, config=config)
    assert state.estimate_kbps == 812.5
    quiet = ReceiverReport(1.1, 0.1, 0, 0, 0, 4, None, None)
    state = remb_update(state, quiet, now_s=1.1, outstanding_bits=8000, config=config)
    assert state.estimate_kbps == 812.5
    tiny = ReceiverReport(1.2, 0.1, 800, 1, 0, 5, 1.0, 0.001)
    assert remb_update(state, tiny, now_s=1.2, outstanding_bits=0, config=config).estimate_kbps == (
        config.min_kbps
    )
