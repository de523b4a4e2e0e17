"""Delivery reports: trains read a bursty link as capacity, loss from gaps, queueing delay."""

from __future__ import annotations

import pytest

from uma.control.delivery import DeliverySettings, DeliveryTracker


def _fifo(capacity_kbps, sends, *, delay_ms=20.0):
    """Arrival times of (send_ms, bits) through a FIFO of the given capacity (bits per ms)."""
    free, out = 0.0, []
    for send_ms, bits in sends:
        free = max(free, send_ms) + bits / capacity_kbps
        out.append((send_ms, free + delay_ms, bits))
    return out


def _feed(tracker, arrivals):
    reports = []
    for seq, (send_ms, arrival_ms, bits) in enumerate(arrivals):
        report = tracker.on_packet(seq, send_ms, arrival_ms, bits)
        if report is not None:
            reports.append(report)
    return reports


def test_frames_sent_in_bursts_measure_the_link_not_the_send_rate():
    # 200 kbit/s of video in 4-packet frames every 40 ms over a 1,000 kbit/s link
    sends = [(40.0 * f, 2000) for f in range(100) for _ in range(4)]
    reports = _feed(DeliveryTracker(), _fifo(1000.0, sends))
    capacities = [r.capacity_kbps for r in reports if r.capacity_kbps is not None]
    assert capacities and all(c == pytest.approx(1000.0, rel=1e-6) for c in capacities)
    assert all(r.queue_delay_last_ms < 10.0 for r in reports)  # no standing queue
    assert reports[-1].received_kbps < 400.0


def _scheduler(sends, *, per_slot, slot_ms=40.0, delay_ms=20.0):
    """A cellular scheduler: every `slot_ms` it delivers up to `per_slot` queued packets at once."""
    out, queue, slot = [], list(sends), 1
    while queue:
        t = slot * slot_ms
        ready = [p for p in queue if p[0] < t][:per_slot]
        for k, (send_ms, bits) in enumerate(ready):
            out.append((send_ms, t + delay_ms + 0.01 * k, bits))
            queue.remove((send_ms, bits))
        slot += 1
    return out


def test_clumped_delivery_of_a_busy_link_reads_as_its_mean_rate():
    # the sender offers 8 packets per 40 ms, the scheduler delivers 4 per 40 ms in one clump
    sends = [(40.0 * f + 0.001 * k, 9600) for f in range(100) for k in range(8)]
    reports = _feed(DeliveryTracker(), _scheduler(sends, per_slot=4))
    pooled_bits = sum(r.train_bits for r in reports)
    pooled_ms = sum(r.train_ms for r in reports)
    assert pooled_bits / pooled_ms == pytest.approx(4 * 9600 / 40.0, rel=0.01)


def test_a_sender_pause_is_forgiven_on_an_idle_link():
    # one small packet every 40 ms on a fast link: no train, the send rate is not measured
    sends = [(40.0 * f, 800) for f in range(50)]
    reports = _feed(DeliveryTracker(), _fifo(5000.0, sends))
    assert all(r.capacity_kbps is None for r in reports)


def test_loss_from_sequence_gaps_and_a_late_packet_is_not_lost():
    tracker = DeliveryTracker(DeliverySettings(interval_ms=1000.0))
    for seq in (0, 1, 2, 5, 6):  # 3 and 4 missing
        tracker.on_packet(seq, 10.0 * seq, 10.0 * seq + 20.0, 1000)
    tracker.on_packet(3, 30.0, 75.0, 1000)  # 3 arrives late
    report = tracker.flush(100.0)
    assert report.lost == 1
    assert report.packets == 6
    assert report.loss_fraction == pytest.approx(1 / 7)


def test_queueing_delay_is_one_way_delay_above_the_smallest():
    tracker = DeliveryTracker(DeliverySettings(interval_ms=1000.0))
    for seq, owd in enumerate((50.0, 30.0, 45.0, 130.0)):
        tracker.on_packet(seq, 10.0 * seq, 10.0 * seq + owd, 1000)
    report = tracker.flush(200.0)
    assert report.queue_delay_ms == (0.0, 0.0, 15.0, 100.0)


def test_a_report_each_interval_of_arrivals():
    tracker = DeliveryTracker(DeliverySettings(interval_ms=100.0))
    reports = _feed(tracker, [(10.0 * k, 10.0 * k + 20.0, 1000) for k in range(35)])
    assert len(reports) == 3
    assert sum(r.packets for r in reports) == 31


def test_without_an_interval_only_flush_closes_a_report():
    tracker = DeliveryTracker(DeliverySettings(interval_ms=None))
    assert _feed(tracker, [(10.0 * k, 10.0 * k + 20.0, 1000) for k in range(35)]) == []
    report = tracker.flush(400.0)
    assert report.packets == 35 and report.received_bits == 35_000


@pytest.mark.parametrize("field", ["interval_ms", "base_window_ms"])
def test_settings_refuse_a_bad_value_naming_it(field):
    with pytest.raises(ValueError, match=field):
        DeliverySettings(**{field: 0.0})
