"""uma's controller after a silence cut: the recovery probe (`recover_after_silence`)."""

from __future__ import annotations

import pytest

from uma.control import UmaController, UmaSettings
from uma.control.delivery import DeliveryReport


def _report(start_ms, end_ms, *, bits=2_000, queue_ms=(40.0,), train_kbps=None):
    """A report of `len(queue_ms)` packets; with `train_kbps`, 50 ms of train at that rate."""
    train_ms = 50.0 if train_kbps else 0.0
    return DeliveryReport(
        start_ms=start_ms, end_ms=end_ms, packets=len(queue_ms), received_bits=bits, lost=0,
        train_bits=int((train_kbps or 0) * train_ms), train_ms=train_ms,
        queue_delay_ms=tuple(queue_ms), records=(),
    )  # fmt: skip


def _cut(recover: bool, *, bits: int = 1_000) -> tuple[UmaController, float]:
    """A controller at 24 kbit/s measured, a thin 10 kbit/s stream (application-limited),
    then 250 ms of silence; returns it and the capacity before the cut."""
    controller = UmaController(UmaSettings(initial_kbps=24.0, recover_after_silence=recover))
    for k in range(20):
        controller.on_report(_report(100.0 * k, 100.0 * (k + 1), bits=bits, queue_ms=(2.0,)))
    before = controller.capacity_kbps
    assert controller.on_silence(2250.0).reason == "silence"
    assert controller.capacity_kbps == pytest.approx(max(bits / 100.0 * 0.25, 5.0))
    return controller, before


@pytest.mark.parametrize("recover", [False, True])
def test_after_a_cut_a_probe_for_the_estimate_before_it_and_its_measurement_taken(recover):
    """The first report with packets (they queued: no spurious silence) asks for a probe at
    the pre-cut estimate; the next train measurement is taken whole, capped there. Off: the
    usual probe at the cut estimate and a small step."""
    controller, before = _cut(recover)
    decision = controller.on_report(_report(2300.0, 2400.0))
    assert decision.probe is not None
    expected = 0.85 * before if recover else controller.capacity_kbps
    assert decision.probe.rate_kbps == pytest.approx(2.0 * expected)
    controller.on_report(_report(2400.0, 2500.0, train_kbps=60.0))
    if recover:
        assert controller.capacity_kbps == pytest.approx(0.85 * before)  # 60 measured, capped
    else:
        assert controller.capacity_kbps < 0.6 * before  # one train of 50 ms weighs 0.15


def test_a_recovery_measurement_below_the_pre_cut_estimate_is_what_is_taken():
    controller, before = _cut(True)
    controller.on_report(_report(2300.0, 2400.0))
    controller.on_report(_report(2400.0, 2500.0, train_kbps=12.0))
    assert controller.capacity_kbps == pytest.approx(12.0)
    controller.on_report(_report(2500.0, 2600.0, train_kbps=40.0))  # later: weighed as ever
    assert 12.0 < controller.capacity_kbps < 0.6 * 40.0


def test_a_report_naming_a_new_technology_caps_the_probe_by_its_prior():
    """800 kbit/s before the cut, a thin 80 kbit/s stream cut to 20: the probe asks for
    GPRS's 40, not 800, and takes no more."""
    controller = UmaController(UmaSettings(initial_kbps=800.0, recover_after_silence=True))
    for k in range(20):
        controller.on_report(_report(100.0 * k, 100.0 * (k + 1), bits=8_000, queue_ms=(2.0,)))
    controller.on_silence(2250.0)
    assert controller.capacity_kbps == pytest.approx(20.0)
    decision = controller.on_report(_report(2300.0, 2400.0), technology="GPRS")
    assert decision.probe is not None
    assert decision.probe.rate_kbps == pytest.approx(2.0 * 40.0)
    controller.on_handover("GPRS", 2400.0)
    controller.on_report(_report(2400.0, 2500.0, train_kbps=45.0))
    assert controller.capacity_kbps == pytest.approx(40.0)  # 45 measured, the prior's 40


def test_a_spurious_silence_undone_needs_no_recovery_probe():
    controller, before = _cut(True)
    decision = controller.on_report(_report(2300.0, 2400.0, queue_ms=(2.0,)))
    assert controller.capacity_kbps == pytest.approx(before)
    assert decision.probe is None or decision.probe.rate_kbps == pytest.approx(2.0 * before)
    controller.on_report(_report(2400.0, 2500.0, train_kbps=60.0))
    assert controller.capacity_kbps < 60.0 * 0.6  # no measurement taken whole


def test_no_recovery_probe_while_the_link_still_holds_a_backlog_nor_a_backlogged_measurement():
    """Packets that queued 200 ms (a backlog draining): no recovery probe yet; the first
    report with no backlog asks for it; a measurement whose report shows a backlog again is
    only weighed as ever."""
    controller, before = _cut(True)
    assert controller.on_report(_report(2300.0, 2400.0, queue_ms=(200.0,))).probe is None
    decision = controller.on_report(_report(2400.0, 2500.0))
    assert decision.probe is not None
    assert decision.probe.rate_kbps == pytest.approx(2.0 * 0.85 * before)
    controller.on_report(_report(2500.0, 2600.0, train_kbps=60.0, queue_ms=(200.0,)))
    assert controller.capacity_kbps < 0.6 * before


def test_no_recovery_for_a_stream_that_filled_its_estimate_nor_long_after_the_cut():
    """20 of 24 kbit/s arriving is not application-limited: the cut stands as before. A
    thin stream's first clear report 6 s after its cut is too late for a recovery probe."""
    controller, _ = _cut(True, bits=2_000)
    decision = controller.on_report(_report(2300.0, 2400.0))
    assert decision.probe is None or decision.probe.rate_kbps == pytest.approx(10.0)
    controller, _ = _cut(True)
    decision = controller.on_report(_report(8200.0, 8300.0))
    assert decision.probe is None or decision.probe.rate_kbps == pytest.approx(10.0)
