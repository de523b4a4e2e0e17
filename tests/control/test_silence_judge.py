"""A silence judged by the reports that end it (`judge_silence`): hand-worked report sequences.

The sender had 400 kbit/s measured and arriving; the feedback falls silent at 500 ms (the link
is off), so the controller pauses at 650 ms and cuts at 750 ms (x0.25 of 400: 100) and at
1,000 ms (25). What the reports after it say decides whether the cut stands.
"""

from __future__ import annotations

import math

import pytest

from uma.control import UmaController, UmaSettings
from uma.control.delivery import DeliveryReport
from uma.control.silence import SilenceJudge

HELD_KBPS = 400.0


def _report(start_ms, end_ms, *, queue_ms=(2.0,), bits=40_000, train=(0, 0.0), lost=0):
    """A report of `len(queue_ms)` packets (their queueing delays), `bits` over its span and
    `train` = (bits, ms) of the packets that came back to back."""
    return DeliveryReport(
        start_ms=start_ms, end_ms=end_ms, packets=len(queue_ms), received_bits=bits,
        lost=lost, train_bits=train[0], train_ms=train[1], queue_delay_ms=tuple(queue_ms),
        records=(),
    )  # fmt: skip


def _silenced(judge: bool) -> UmaController:
    """400 kbit/s for 500 ms, then no report until 1,000 ms: paused, two cuts."""
    controller = UmaController(UmaSettings(initial_kbps=HELD_KBPS, judge_silence=judge))
    for k in range(5):  # 40,000 bits per 100 ms, trains at 400 kbit/s: measured, no probe
        controller.on_report(_report(100.0 * k, 100.0 * (k + 1), train=(9600, 24.0)))
    assert controller.paused(650.0)
    assert controller.on_silence(750.0).reason == "silence"
    assert controller.on_silence(1000.0).reason == "silence"
    assert controller.capacity_kbps == pytest.approx(HELD_KBPS * 0.25 * 0.25)
    return controller


def _weighed(from_kbps: float, train_kbps: float, train_ms: float) -> float:
    """The controller's usual move toward a train (time constant 300 ms)."""
    return from_kbps + (1.0 - math.exp(-train_ms / 300.0)) * (train_kbps - from_kbps)


def test_an_off_period_that_ends_with_the_backlog_drained_at_the_old_rate_keeps_the_estimate():
    """The packets held up by the off-period (480-380 ms of queue) come out back to back at
    500 kbit/s: the link is back at its old rate. The held 400 is restored (then moved toward
    the train as usual), and the target drains the queue they met: 0.85 x 407.7 less 407.7 x
    (380 - 60) / 500."""
    controller = _silenced(judge=True)
    report = _report(1000.0, 1100.0, queue_ms=(480.0, 420.0, 380.0), train=(12_000, 24.0))
    decision = controller.on_report(report)
    capacity = _weighed(HELD_KBPS, 500.0, 24.0)
    assert controller.capacity_kbps == pytest.approx(capacity)
    assert decision.target_kbps == pytest.approx(capacity * 0.85 - capacity * 320.0 / 500.0)
    assert not controller.paused(1100.0)


def test_without_the_judge_the_same_off_period_keeps_its_cut():
    """Today's rule: the first report with packets decides, and queued packets keep the cut."""
    controller = _silenced(judge=False)
    report = _report(1000.0, 1100.0, queue_ms=(480.0, 420.0, 380.0), train=(12_000, 24.0))
    controller.on_report(report)
    assert controller.capacity_kbps == pytest.approx(_weighed(25.0, 500.0, 24.0))


def test_packets_with_no_train_wait_for_the_report_that_measures_the_drain():
    controller = _silenced(judge=True)
    controller.on_report(_report(1000.0, 1100.0, queue_ms=(450.0,)))  # one packet: no train
    assert controller.capacity_kbps == pytest.approx(25.0)
    controller.on_report(_report(1100.0, 1200.0, queue_ms=(300.0, 250.0), train=(9600, 20.0)))
    assert controller.capacity_kbps == pytest.approx(_weighed(HELD_KBPS, 480.0, 20.0))


@pytest.mark.parametrize(
    "train, lost",
    [
        ((9600, 96.0), 0),  # 100 kbit/s: the link came back slower
        ((12_000, 24.0), 1),  # a loss
    ],
)
def test_a_link_back_slower_or_losing_keeps_the_cut(train, lost):
    controller = _silenced(judge=True)
    controller.on_report(_report(1000.0, 1100.0, queue_ms=(480.0, 400.0), train=train, lost=lost))
    assert controller.capacity_kbps == pytest.approx(_weighed(25.0, train[0] / train[1], train[1]))


def test_a_long_outage_keeps_the_cut_however_fast_the_link_comes_back():
    """Past `judge_window_ms` (1.5 s) from the silence's start the cut stands."""
    controller = _silenced(judge=True)
    for now_ms in (1250.0, 1500.0, 1750.0, 2000.0):
        controller.on_silence(now_ms)
    report = _report(2000.0, 2100.0, queue_ms=(1500.0, 1400.0), train=(12_000, 24.0))
    controller.on_report(report)
    assert controller.capacity_kbps == pytest.approx(_weighed(5.0, 500.0, 24.0))


def test_a_handover_gap_still_pauses_and_lowers():
    """The same silence ended by a report naming a new technology: the paused sender's cut
    stands whatever the old path's last packets measured, and the prior caps it."""
    controller = _silenced(judge=True)
    report = _report(1000.0, 1100.0, queue_ms=(480.0, 420.0, 380.0), train=(12_000, 24.0))
    controller.on_report(report, technology="GPRS")
    assert controller.capacity_kbps == pytest.approx(_weighed(25.0, 500.0, 24.0))
    controller.on_handover("GPRS", 1100.0)
    assert controller.capacity_kbps <= 40.0


def test_the_judge_holds_the_estimate_before_the_first_unjudged_cut():
    judge = SilenceJudge()
    judge.on_cut(400.0, 500.0)
    judge.on_cut(100.0, 500.0)  # the second cut of the same silence
    assert judge.held_kbps == 400.0 and judge.since_ms == 500.0
    judge.forget()
    assert judge.held_kbps is None


@pytest.mark.parametrize("field, value", [("judge_fraction", 0.0), ("judge_window_ms", 0.0)])
def test_the_judges_settings_refuse_bad_values(field, value):
    with pytest.raises(ValueError, match=field):
        UmaSettings(**{field: value})
