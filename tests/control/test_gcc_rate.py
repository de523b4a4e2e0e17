"""GCC's AIMD and loss controllers against hand-worked cases, and the controller's probes."""

from __future__ import annotations

import pytest

from uma.control.delivery import DeliveryReport, PacketRecord
from uma.control.gcc import GccController
from uma.control.gcc_delay import Usage
from uma.control.gcc_rate import (
    TRANSITIONS,
    AimdController,
    AimdState,
    GccRateSettings,
    LossController,
)


def test_transition_table_is_complete_and_as_the_draft_says():
    assert len(TRANSITIONS) == len(AimdState) * len(Usage)
    assert TRANSITIONS[AimdState.HOLD, Usage.NORMAL] is AimdState.INCREASE
    assert TRANSITIONS[AimdState.DECREASE, Usage.NORMAL] is AimdState.HOLD
    assert TRANSITIONS[AimdState.INCREASE, Usage.UNDER] is AimdState.HOLD
    assert all(TRANSITIONS[state, Usage.OVER] is AimdState.DECREASE for state in AimdState)


def test_decrease_is_085_of_the_received_rate_then_hold():
    aimd = AimdController(GccRateSettings(initial_kbps=1000.0))
    assert aimd.update(Usage.OVER, 800.0, 0.0, 100.0) == pytest.approx(680.0)
    assert aimd.state is AimdState.HOLD
    assert aimd.capacity.mean_kbps == 800.0


def test_multiplicative_increase_far_from_convergence():
    aimd = AimdController(GccRateSettings(initial_kbps=500.0))
    aimd.update(Usage.NORMAL, 500.0, 0.0, 100.0)  # HOLD -> INCREASE, no time yet
    assert aimd.update(Usage.NORMAL, 500.0, 1000.0, 100.0) == pytest.approx(500.0 * 1.08)


def test_additive_increase_near_convergence():
    aimd = AimdController(GccRateSettings(initial_kbps=1000.0))
    aimd.update(Usage.OVER, 800.0, 0.0, 100.0)  # 680, link capacity estimate 800
    aimd.update(Usage.NORMAL, 700.0, 100.0, 100.0)  # HOLD -> INCREASE over 0.1 s
    # 680 kbit/s at 30 frames/s: 22,667 bits a frame in 3 packets of 7,556 bits;
    # response time 100 + 100 ms: 37.8 kbit/s per second, for 0.1 s
    frame_bits = 680.0 * 1000 / 30
    expected = 680.0 + frame_bits / 3 / 200.0 * 0.1
    assert aimd.target_kbps == pytest.approx(expected)


def test_increase_never_beyond_1_5_times_received_plus_10():
    aimd = AimdController(GccRateSettings(initial_kbps=100.0))
    aimd.update(Usage.NORMAL, 50.0, 0.0, 100.0)
    # x1.08 after a second would be 108; the bound is 1.5 x 50 + 10 = 85
    assert aimd.update(Usage.NORMAL, 50.0, 1000.0, 100.0) == pytest.approx(100.0)
    aimd = AimdController(GccRateSettings(initial_kbps=60.0))
    aimd.update(Usage.NORMAL, 50.0, 0.0, 100.0)
    assert aimd.update(Usage.NORMAL, 50.0, 1000.0, 100.0) == pytest.approx(64.8)  # under 85
    aimd = AimdController(GccRateSettings(initial_kbps=80.0))
    aimd.update(Usage.NORMAL, 50.0, 0.0, 100.0)
    assert aimd.update(Usage.NORMAL, 50.0, 1000.0, 100.0) == pytest.approx(85.0)  # 86.4 capped


def test_the_bound_does_not_undo_a_probe():
    """An application-limited sender (50 kbit/s received) whose probe showed 1,000: the target
    stays at 1,000, neither raised further nor pulled down to 1.5 x received + 10."""
    aimd = AimdController(GccRateSettings(initial_kbps=60.0))
    aimd.update(Usage.NORMAL, 50.0, 0.0, 100.0)
    aimd.raise_to(1000.0)
    assert aimd.update(Usage.NORMAL, 50.0, 1000.0, 100.0) == pytest.approx(1000.0)


def test_loss_above_10_percent_cuts_by_half_the_loss():
    loss = LossController(GccRateSettings(initial_kbps=1000.0))
    assert loss.update(0.2, 0.0, 1000.0) == pytest.approx(900.0)


def test_loss_between_2_and_10_percent_holds_and_below_2_grows_5_percent_a_second():
    loss = LossController(GccRateSettings(initial_kbps=1000.0))
    loss.update(0.2, 0.0, 1000.0)  # 900
    assert loss.update(0.05, 1000.0, 500.0) == pytest.approx(900.0)
    assert loss.update(0.0, 2000.0, 500.0) == pytest.approx(945.0)


def _report(records, end_ms, lost=0):
    return DeliveryReport(
        start_ms=records[0].arrival_ms,
        end_ms=end_ms,
        packets=len(records),
        received_bits=sum(r.size_bits for r in records),
        lost=lost,
        train_bits=0,
        train_ms=0.0,
        queue_delay_ms=tuple(0.0 for _ in records),
        records=tuple(records),
    )


def test_gcc_probes_at_start_with_3x_then_6x_the_initial_rate():
    gcc = GccController(GccRateSettings(initial_kbps=300.0))
    records = [PacketRecord(k, 40.0 * k, 40.0 * k + 20.0, 9600) for k in range(3)]
    first = gcc.on_report(_report(records, 100.0))
    second = gcc.on_report(_report(records, 200.0))
    assert first.probe.rate_kbps == 900.0 and second.probe.rate_kbps == 1800.0


def test_gcc_target_is_the_smaller_of_delay_and_loss_based():
    gcc = GccController(GccRateSettings(initial_kbps=1000.0))
    records = [PacketRecord(k, 10.0 * k, 10.0 * k + 20.0, 9600) for k in range(10)]
    decision = gcc.on_report(_report(records, 120.0, lost=5))  # a third lost
    assert decision.target_kbps == pytest.approx(1000.0 * (1 - 0.5 * 5 / 15))
