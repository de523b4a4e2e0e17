"""uma's controller with `queue_from_owed`: the queue ahead is at most what the link still owes."""

from __future__ import annotations

import pytest

from uma.control import UmaController, UmaSettings
from uma.control.delivery import DeliveryReport


def _train(end_ms: float, queue_ms: float, *, packets: int = 24) -> DeliveryReport:
    """`packets` of 9,600 bits that came out back to back at 1,000 kbit/s, each having met
    `queue_ms` of queue."""
    bits = packets * 9600
    return DeliveryReport(
        start_ms=end_ms - 100.0, end_ms=end_ms, packets=packets, received_bits=bits, lost=0,
        train_bits=bits, train_ms=bits / 1000.0, queue_delay_ms=(queue_ms,) * packets,
        records=(),
    )  # fmt: skip


def _settled(owed: bool) -> UmaController:
    controller = UmaController(UmaSettings(initial_kbps=1000.0, queue_from_owed=owed))
    for k in range(10):
        controller.on_report(_train(100.0 * (k + 1), 2.0), owed_bits=0)
    assert controller.capacity_kbps == pytest.approx(1000.0)
    return controller


@pytest.mark.parametrize("owed", [False, True])
def test_a_backlog_the_paused_sender_left_nothing_behind_is_not_drained(owed):
    """Packets that waited 900 ms (an outage) with nothing sent after them: the drain term
    reads 1,000 x (900 - 60) / 500 = 1,680 kbit/s of standing queue and clamps the target to
    `min_kbps`, unless the queue is taken from what is owed (none: the target stays at the
    capacity's 850)."""
    controller = _settled(owed)
    decision = controller.on_report(_train(1100.0, 900.0), owed_bits=0)
    assert controller.queue_ms == (0.0 if owed else 900.0)
    assert decision.target_kbps == pytest.approx(850.0 if owed else 5.0)


@pytest.mark.parametrize("owed_bits, queue_ms", [(None, 900.0), (900_000, 900.0), (200_000, 200.0)])
def test_a_queue_still_owed_is_drained(owed_bits, queue_ms):
    """With the key, 900 ms of queue stands when 900 ms of bits (at the 1,000-kbit/s estimate)
    are still owed or the owed bits are not known; with 200 ms owed, 200 ms of it does:
    1,000 x 0.85 - 1,000 x (200 - 60) / 500 = 570 kbit/s."""
    controller = _settled(True)
    decision = controller.on_report(_train(1100.0, 900.0), owed_bits=owed_bits)
    assert controller.queue_ms == pytest.approx(queue_ms)
    expected_kbps = max(850.0 - 1000.0 * (queue_ms - 60.0) / 500.0, 5.0)
    assert decision.target_kbps == pytest.approx(expected_kbps)


def test_the_key_is_on_by_default():
    assert UmaSettings().queue_from_owed is True
