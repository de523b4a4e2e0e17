"""A refresh under way at a handover: its packets wait once the reports are later than their
own spacing allows, and what is left of it when the new technology is named is dropped if it
would hold the new link for more than `handover_drain_ms` (`uma.engine.rate.ReportSpacing`,
`RateControl.refresh_held`, `RefreshPlanner.on_handover`)."""

import pytest

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.config.codecs import RefreshConfig
from uma.control import DeliverySettings, DeliveryTracker
from uma.engine.rate import ReportSpacing, make_rate
from uma.engine.records import Tally
from uma.engine.refresh import RefreshEvent, RefreshPlanner
from uma.engine.reports import ReceiverReport

FPS = 25.0


def test_report_spacing_is_smoothed_as_a_round_trip_and_bounded():
    """Reports every 100 ms: the first spacing sets 100 ms and a deviation of 50 (allowed
    300, bounded to 150); each regular spacing after it keeps 3/4 of the deviation, so after
    12 spacings it is 50 x 0.75^11 = 2.11 ms and a report is late 108.4 ms after the last."""
    spacing = ReportSpacing()
    assert spacing.allowed_ms is None and not spacing.late(5.0)
    spacing.on_report(0.0)
    spacing.on_report(0.1)
    assert spacing.allowed_ms == pytest.approx(150.0)
    for i in range(2, 13):
        spacing.on_report(i / 10.0)
    assert spacing.deviation_ms == pytest.approx(50.0 * 0.75**11)
    assert spacing.allowed_ms == pytest.approx(100.0 + 4.0 * 50.0 * 0.75**11)
    assert not spacing.late(1.2 + 0.105) and spacing.late(1.2 + 0.110)
    # Jittery reports (60 and 140 ms apart) allow longer, never beyond the pause (150 ms).
    jitter = ReportSpacing()
    t = 0.0
    for i in range(40):
        t += 0.06 if i % 2 else 0.14
        jitter.on_report(t)
    assert 140.0 < jitter.allowed_ms <= 150.0


def report(tracker: DeliveryTracker, now_s: float, technology: str) -> ReceiverReport:
    delivery = tracker.flush(now_s * 1000.0)
    return ReceiverReport(
        now_s, 0.1, delivery.received_bits, delivery.packets, delivery.lost, -1, 0.0,
        technology=technology, delivery=delivery,
    )  # fmt: skip


def test_a_handover_with_a_refresh_under_way_hand_worked():
    """GPRS reports every 100 ms, each 20 ms on its way, until the gap (the last report
    before it arrives at 1.0 s); the next comes at 1.6 s and names GSM. Nine regular
    spacings leave a deviation of 50 x 0.75^8 = 5.0 ms: a report is late 120.0 ms after the
    last. A predicted refresh of four 4,320-bit packets is coded at 0.92 s, 23.2 kbit/s spare:
    - 0.92: one packet leaves (the first needs no credit; the credit is now -4,320 bits);
    - 1.00, 1.08: 80 ms of credit each (1,856 bits): -2,464, then -608: nothing leaves;
    - 1.13: 50 ms more (1,160 bits) would let the second packet go, but the reports are late
      (130 ms, 120.0 allowed; the controller's pause comes only at 150 ms): held, and no
      credit saved; 1.20-1.56: held (paused);
    - 1.60: the report names GSM; the estimate is now at most GSM's prior (9.6 kbit/s): the
      3 packets left (12,960 bits) would take more than 1.3 s, over 500 ms: dropped, and the
      next refresh is intra."""
    rate = make_rate(
        EngineConfig(estimator=EstimatorConfig(initial_kbps=30.0, kind="uma")), FeedbackConfig()
    )
    tracker = DeliveryTracker(DeliverySettings(interval_ms=1e9))
    plan = RefreshPlanner(RefreshConfig(enabled=True, min_spare_kbps=4.0))
    plan.fire(RefreshEvent.ENTER)
    plan.spare_kbps, plan.intra_due = 23.2, False  # a stream under way

    def gprs_report(tick: int) -> None:  # one 600-bit packet in each
        now_s = tick / 10.0
        tracker.on_packet(tick, (now_s - 0.07) * 1000.0, (now_s - 0.03) * 1000.0, 600)
        gprs = report(tracker, now_s - 0.02, "GPRS")
        rate.on_report(gprs, now_s)
        assert not rate.handover and rate.technology == "GPRS"  # no new technology
        assert plan.on_report(gprs, now_s, rate.state.estimate_kbps, rate.handover) == []

    for tick in range(1, 10):  # reports at 0.1 ... 0.9 s
        gprs_report(tick)
    plan.coded([(f"p{i}", 4320) for i in range(4)], 0.92, intra=False)
    left = {0.92: len(plan.pace(0.92, queue_delay_ms=0.0, held=rate.refresh_held(0.92)))}
    gprs_report(10)
    assert rate.spacing.allowed_ms == pytest.approx(100.0 + 4.0 * 50.0 * 0.75**8)
    for t in (1.0, 1.08, 1.13, 1.2, 1.32, 1.44, 1.56):
        left[t] = len(plan.pace(t, queue_delay_ms=0.0, held=rate.refresh_held(t)))
    assert left == {0.92: 1, 1.0: 0, 1.08: 0, 1.13: 0, 1.2: 0, 1.32: 0, 1.44: 0, 1.56: 0}
    assert plan.credit_bits == pytest.approx(-608.0)  # nothing accrued while held
    assert not rate.paused(1.13) and rate.refresh_held(1.13) and rate.paused(1.2)
    assert not rate.refresh_held(1.08)
    for t in (1.2, 1.4):
        rate.on_silence(t)
    gsm = report(tracker, 1.58, "GSM")
    rate.on_report(gsm, 1.6)
    estimate_kbps = rate.state.estimate_kbps
    assert estimate_kbps <= 9.6
    assert rate.handover and rate.technology == "GSM"
    assert plan.on_report(gsm, 1.6, estimate_kbps, False) == []  # no handover: kept
    actions = plan.on_report(gsm, 1.6, estimate_kbps, rate.handover)
    assert Tally("refresh_dropped") in actions and not plan.queue and plan.intra_due


def test_a_refresh_that_drains_quickly_on_the_new_link_is_kept():
    plan = RefreshPlanner(RefreshConfig(enabled=True))
    plan.fire(RefreshEvent.ENTER)
    plan.intra_due = False
    plan.coded([(f"p{i}", 4320) for i in range(3)], 0.0, intra=False)
    assert plan.on_handover(0.5, 30.0) == []  # 12,960 bits at 30 kbit/s: 432 ms
    assert len(plan.queue) == 3 and not plan.intra_due
    assert plan.on_handover(0.6, 25.0)  # 518 ms: dropped
    assert not plan.queue


def test_the_oracle_and_the_other_kinds_hold_the_refresh_only_while_paused():
    for kind in ("gcc", "webrtc"):
        rate = make_rate(EngineConfig(estimator=EstimatorConfig(kind=kind)), FeedbackConfig())
        assert not rate.refresh_held(10.0)
    oracle = make_rate(
        EngineConfig(estimator=EstimatorConfig(kind="uma"), policy="oracle"), FeedbackConfig()
    )
    oracle.spacing.on_report(0.0)
    oracle.spacing.on_report(0.1)
    assert not oracle.refresh_held(5.0)
    tracker = DeliveryTracker(DeliverySettings(interval_ms=1e9))
    for now_s, technology in ((0.2, "3G"), (0.3, "GPRS")):
        oracle.on_report(report(tracker, now_s, technology), now_s)
    assert oracle.technology == "GPRS" and not oracle.handover  # the oracle drops no refresh
