"""WebRTC's receiver-side estimator (aiortc) in a closed loop over one bottleneck."""

import numpy as np
import pytest

pytest.importorskip("aiortc")

from uma.bench.estimator_loop import closed_loop, step_response  # noqa: E402
from uma.config.scenario import EngineConfig, FeedbackConfig  # noqa: E402
from uma.control import DeliveryReport, PacketRecord  # noqa: E402
from uma.engine.rate import make_rate  # noqa: E402
from uma.engine.reports import ReceiverReport  # noqa: E402
from uma.engine.webrtc import RembEstimator, abs_send_time  # noqa: E402


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


def _report(records, sent_s):
    delivery = DeliveryReport(
        start_ms=records[0].arrival_ms, end_ms=records[-1].arrival_ms, packets=len(records),
        received_bits=sum(r.size_bits for r in records), lost=0, train_bits=0, train_ms=0.0,
        queue_delay_ms=tuple(0.0 for _ in records), records=tuple(records),
    )  # fmt: skip
    bits = delivery.received_bits
    return ReceiverReport(
        sent_s, 0.1, bits, len(records), 0, records[-1].seq, 0.0, delivery=delivery
    )


def test_the_engine_runs_aiortc_over_the_reported_packets():
    """`WebrtcRate` feeds aiortc's estimator each report's packets: its estimate is the one a
    receiver fed the same packets would send as a REMB; silence lowers it."""
    config = EngineConfig(estimator={"kind": "webrtc"})
    rate = make_rate(config, FeedbackConfig())
    direct = RembEstimator()
    seq = 0
    for report_index in range(60):  # 6 s of 800 kbit/s in 1,000-byte packets, 10 ms apart
        records = []
        for _ in range(10):
            send_ms = seq * 10.0
            records.append(PacketRecord(seq, send_ms, send_ms + 30.0, 8000))
            direct.on_packet(
                arrival_s=(send_ms + 30.0) / 1000, sent_s=send_ms / 1000, size_bits=8000
            )
            seq += 1
        probe, _ = rate.on_report(
            _report(records, records[-1].arrival_ms / 1000), report_index / 10
        )
        assert probe is None
    assert direct.estimate_kbps is not None
    assert rate.state.estimate_kbps == pytest.approx(direct.estimate_kbps)
    before = rate.state.estimate_kbps
    assert rate.on_silence(5.95) == [] and rate.state.estimate_kbps == before
    rate.on_silence(6.5)
    assert rate.state.estimate_kbps == pytest.approx(0.85 * before)
