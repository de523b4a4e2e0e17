"""The controller's reading of a drop that a building queue confirms: `take_queued_drop` (D)
and `bounded_queued_drop` (Q), on hand-worked reports (docs/rate-control.md, rc15 and rc16)."""

from __future__ import annotations

import math

import pytest

from uma.control import UmaController, UmaSettings
from uma.control.delivery import DeliveryReport


def _train(end_ms, *, kbps, queue_ms):
    """A report whose packets made a 100-ms train at `kbps` and met `queue_ms` of queue."""
    return DeliveryReport(
        start_ms=end_ms - 100.0, end_ms=end_ms, packets=len(queue_ms),
        received_bits=int(kbps * 100), lost=0, train_bits=int(kbps * 100), train_ms=100.0,
        queue_delay_ms=tuple(queue_ms), records=(),
    )  # fmt: skip


@pytest.mark.parametrize(
    ("taken", "queue_ms", "whole"),
    [(False, (20.0, 90.0), False), (True, (20.0, 90.0), True), (True, (90.0, 20.0), False),
     (True, (20.0, 50.0), False)],
)  # fmt: skip
def test_a_train_below_the_estimate_in_a_building_queue_is_taken_whole(taken, queue_ms, whole):
    """1,000 kbit/s estimated, a train reads 400 while the queue rises 20 -> 90 ms (past the
    60-ms target): with `take_queued_drop` the estimate is 400; without it (or with the queue
    falling, or staying under the target) the usual weighing moves it about a quarter."""
    controller = UmaController(UmaSettings(initial_kbps=1000.0, take_queued_drop=taken))
    controller.on_report(_train(100.0, kbps=400.0, queue_ms=queue_ms))
    weighed = 1000.0 - 600.0 * (1.0 - math.exp(-100.0 / 300.0))
    assert controller.capacity_kbps == pytest.approx(400.0 if whole else weighed)


@pytest.mark.parametrize("bounded", [False, True])
def test_a_drop_read_in_a_building_queue_halves_the_estimate_per_report(bounded):
    """1,000 kbit/s estimated; two 100-ms trains read 400 while the queue builds 10 -> 45 ms,
    then 45 -> 80 (past the 20-ms low mark). With `bounded_queued_drop` the first report cuts
    to 500 (at most a half per report), the second takes the train whole (400 > 250); without
    it each moves the estimate 1 - exp(-100/300) = 0.283 of the way."""
    controller = UmaController(UmaSettings(initial_kbps=1000.0, bounded_queued_drop=bounded))
    weight = 1.0 - math.exp(-100.0 / 300.0)
    controller.on_report(_train(100.0, kbps=400.0, queue_ms=(10.0, 45.0)))
    first = 1000.0 - 600.0 * weight
    assert controller.capacity_kbps == pytest.approx(500.0 if bounded else first)
    controller.on_report(_train(200.0, kbps=400.0, queue_ms=(45.0, 80.0)))
    assert controller.capacity_kbps == pytest.approx(
        400.0 if bounded else first - (first - 400.0) * weight
    )


@pytest.mark.parametrize("queue_ms", [(45.0, 10.0), (5.0, 15.0), (30.0, 30.0)])
def test_a_low_train_without_a_building_queue_is_weighed_as_usual(queue_ms):
    """The same 400-kbit/s train with the queue falling, staying under the 20-ms low mark, or
    flat: bursty delivery, not a drop the queue confirms; the usual weighing (0.283)."""
    controller = UmaController(UmaSettings(initial_kbps=1000.0, bounded_queued_drop=True))
    controller.on_report(_train(100.0, kbps=400.0, queue_ms=queue_ms))
    weighed = 1000.0 - 600.0 * (1.0 - math.exp(-100.0 / 300.0))
    assert controller.capacity_kbps == pytest.approx(weighed)


def test_a_bounded_drop_never_cuts_less_than_the_usual_weighing():
    """A 900-ms train at 100 kbit/s (weight 0.95) in a building queue: the usual weighing
    already cuts below half (145 kbit/s); the bound does not raise it back to 500."""
    controller = UmaController(UmaSettings(initial_kbps=1000.0, bounded_queued_drop=True))
    report = DeliveryReport(
        start_ms=0.0, end_ms=1000.0, packets=2, received_bits=90_000, lost=0,
        train_bits=90_000, train_ms=900.0, queue_delay_ms=(10.0, 90.0), records=(),
    )  # fmt: skip
    controller.on_report(report)
    assert controller.capacity_kbps == pytest.approx(1000.0 - 900.0 * (1.0 - math.exp(-3.0)))
