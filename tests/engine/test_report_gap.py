"""Numbered reports with cumulative counters: what a lost report held reaches the sender with
the next one (`report_gap`, `span_since`)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from uma.engine.reports import ReceiverReport, report_gap, span_since


def numbered(seq, bits, packets, lost, totals, *, sent_s=None, delivery=None, earlier=()):
    """The report `seq` of an interval with `bits`, `packets`, `lost`; `totals` the running
    (bits, packets, lost) before it, returned updated."""
    total = (totals[0] + bits, totals[1] + packets, totals[2] + lost)
    report = ReceiverReport(
        0.1 * (seq + 1) if sent_s is None else sent_s, 0.1, bits, packets, lost, -1, None,
        delivery=delivery, seq=seq, total_bits=total[0], total_packets=total[1],
        total_lost=total[2], earlier=earlier,
    )  # fmt: skip
    return report, total


def test_a_lost_reports_bits_appear_in_the_next_one():
    totals = (0, 0, 0)
    first, totals = numbered(0, 8000, 2, 0, totals)
    _lost, totals = numbered(1, 12_000, 3, 1, totals)
    third, totals = numbered(2, 4000, 1, 0, totals)
    gap = report_gap(first, third)
    assert (gap.missed, gap.bits, gap.packets, gap.lost, gap.stale) == (1, 12_000, 3, 1, False)
    spanned = span_since(first, third)
    assert spanned.received_bits == 16_000 and spanned.packets_received == 4
    assert spanned.packets_lost == 1
    assert abs(spanned.interval_s - 0.2) < 1e-9  # from the first's sending to the third's
    assert span_since(first, first) is first
    assert report_gap(third, first).stale


def test_unnumbered_reports_have_no_gap():
    plain = ReceiverReport(0.1, 0.1, 8000, 2, 0, 1, None)
    totals = (0, 0, 0)
    later, _ = numbered(5, 100, 1, 0, totals)
    assert report_gap(plain, later) == report_gap(None, later)
    assert not report_gap(plain, later).missed
    assert span_since(plain, later) is later


@settings(max_examples=80, deadline=None)
@given(
    intervals=st.lists(
        st.tuples(st.integers(0, 50_000), st.integers(0, 40), st.integers(0, 5), st.booleans()),
        min_size=1,
        max_size=40,
    )
)
def test_the_reports_seen_account_for_every_bit_up_to_the_last(intervals):
    """Whatever reports are lost on the way, folding each seen one's gap gives the receiver's
    totals up to the last one seen, and the missed counts add up to the reports lost."""
    totals = (0, 0, 0)
    seen, last = [], None
    for seq, (bits, packets, lost, arrives) in enumerate(intervals):
        report, totals = numbered(seq, bits, packets, lost, totals)
        if arrives:
            seen.append((report_gap(last, report), report))
            last = report
    if not seen:
        return
    bits = sum(g.bits + r.received_bits for g, r in seen)
    packets = sum(g.packets + r.packets_received for g, r in seen)
    lost = sum(g.lost + r.packets_lost for g, r in seen)
    first = seen[0][1]
    assert bits == last.total_bits - first.total_bits + first.received_bits
    assert packets == last.total_packets - first.total_packets + first.packets_received
    assert lost == last.total_lost - first.total_lost + first.packets_lost
    assert sum(g.missed for g, _ in seen) == last.seq - first.seq + 1 - len(seen)
    assert not any(g.stale for g, _ in seen)
