"""Properties of the delivery reports over random traffic (hypothesis)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from uma.control.delivery import DeliverySettings, DeliveryTracker

frames = st.lists(
    st.tuples(st.floats(0.0, 200.0), st.integers(1, 6), st.integers(400, 12_000)),
    min_size=2,
    max_size=60,
)


@settings(max_examples=60, deadline=None)
@given(frames=frames, capacity_kbps=st.floats(10.0, 5000.0))
def test_a_fifo_never_reads_faster_than_its_capacity(frames, capacity_kbps):
    # without the grace for clock jitter: with it, a packet that found the link just idle
    # (within grace_ms) may count a gap shorter than its own serialisation
    tracker = DeliveryTracker(DeliverySettings(interval_ms=50.0, grace_ms=0.0))
    now = free = 0.0
    seq = 0
    reports = []
    for gap_ms, packets, bits in frames:
        now += gap_ms
        for _ in range(packets):
            free = max(free, now) + bits / capacity_kbps
            report = tracker.on_packet(seq, now, free + 20.0, bits)
            seq += 1
            if report is not None:
                reports.append(report)
    reports.append(tracker.flush(free + 20.0))
    for report in reports:
        if report.capacity_kbps is not None:
            assert report.capacity_kbps <= capacity_kbps * (1 + 1e-6)


@settings(max_examples=60, deadline=None)
@given(dropped=st.sets(st.integers(1, 98)))
def test_lost_counts_exactly_the_missing_sequence_numbers(dropped):
    tracker = DeliveryTracker(DeliverySettings(interval_ms=1e9))
    for seq in range(100):
        if seq not in dropped:
            tracker.on_packet(seq, 10.0 * seq, 10.0 * seq + 20.0, 1000)
    report = tracker.flush(2000.0)
    assert report.lost == len(dropped)
    assert report.packets == 100 - len(dropped)
