"""`engine.climb_back`: after a silence's cuts are undone, straight back to the rung before them
(hand-worked on the H.264 ladder's shape, `test_policy_climb.RUNGS`)."""

from __future__ import annotations

import pytest

from tests.engine.test_policy_climb import RUNGS, view
from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.control import DeliveryReport
from uma.engine import ReceiverReport, UmaEngine
from uma.engine.points import OperatingPoint
from uma.engine.policy import throughput_policy

POINTS = tuple(OperatingPoint("h264", r, fps, w, h, compute_ms=4.0) for r, w, h, fps in RUNGS)


def test_the_policy_goes_back_at_once_to_the_rung_the_budget_carries_up_to_back_to():
    # budget 850 from 16 (SQCIF), within the hold: back to 768 (CIF), no margin (960 > 850)
    assert throughput_policy(view(current=0, last_switch_s=9.99, back_to=8)) == 7
    # capped at the rung before the cuts
    assert throughput_policy(view(current=0, last_switch_s=9.99, back_to=5)) == 5
    # without it: the hold
    assert throughput_policy(view(current=0, last_switch_s=9.99)) == 0
    # never down to it, and at or below the current rung the climb is as ever
    assert throughput_policy(view(current=6, last_switch_s=9.99, back_to=2)) == 6
    assert throughput_policy(view(current=0, back_to=0)) == 1  # one size up, after the hold
    assert throughput_policy(view(current=0, last_switch_s=9.99, back_to=0)) == 0
    assert throughput_policy(view(current=8, estimate_kbps=100.0, back_to=8)) == 3


def _report(end_ms: float, queue_ms: float, rate_kbps: float = 2000.0) -> ReceiverReport:
    """Ten 9,600-bit packets that came out back to back at `rate_kbps`, each having met
    `queue_ms` of queue, over the 100 ms before `end_ms`."""
    n, bits = 10, 9600
    delivery = DeliveryReport(
        start_ms=end_ms - 100.0, end_ms=end_ms, packets=n, received_bits=n * bits, lost=0,
        train_bits=(n - 1) * bits, train_ms=(n - 1) * bits / rate_kbps,
        queue_delay_ms=(queue_ms,) * n, records=(),
    )  # fmt: skip
    return ReceiverReport(end_ms / 1000.0, 0.1, n * bits, n, 0, 0, 20.0, delivery=delivery)


def _rungs(climb_back: bool, after_kbps: float) -> list[tuple[float, int]]:
    """A 2,000-kbit/s link with a report every 100 ms to 1.0 s, silent to 2.2 s, then a report
    of packets that waited 800 ms and came out at `after_kbps`, then reports with no queue:
    (time, rung) at each change of rung, frames at 25 frames/s from 1.0 s."""
    config = EngineConfig(
        estimator=EstimatorConfig(kind="uma", initial_kbps=2000.0, judge_silence=True),
        climb_back=climb_back,
    )
    engine = UmaEngine(config, points=POINTS, source_fps=25.0, feedback=FeedbackConfig())
    for k in range(1, 11):
        engine.on_report(_report(100.0 * k, 2.0), 0.1 * k)
    changes = [(1.0, engine.rung)]
    for frame in range(26, 100):
        now_ms = 40.0 * frame
        if now_ms == 2200.0:
            engine.on_report(_report(2200.0, 800.0, after_kbps), 2.2)
        elif now_ms > 2200.0 and now_ms % 100.0 == 0.0:
            engine.on_report(_report(now_ms, 2.0), now_ms / 1000.0)
        engine.on_frame(frame, now_ms / 1000.0)
        if engine.rung != changes[-1][1]:
            changes.append((now_ms / 1000.0, engine.rung))
    return changes


CUTS = [(1.0, 8), (1.28, 4), (1.52, 2), (1.76, 0)]  # a silence cut every 250 ms from 1.0 s


@pytest.mark.parametrize(
    ("climb_back", "after_kbps", "after"),
    [
        (True, 2100.0, [(2.4, 8)]),  # undone; back once the next report drains the queue
        (False, 2100.0, [(2.8, 1), (3.8, 2)]),  # a size a second, with the margin
        (True, 900.0, [(2.8, 1), (3.8, 2)]),  # the link came back slower: the cut stands
    ],
)
def test_an_undone_silence_climbs_back_to_the_rung_before_its_cuts(climb_back, after_kbps, after):
    assert _rungs(climb_back, after_kbps) == CUTS + after


def test_off_by_default():
    assert EngineConfig().climb_back is False
