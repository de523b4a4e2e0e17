"""Numbered reports with cumulative counters: what a lost report held reaches the sender with
the next one (`report_gap`, `span_since`), and uma's rate control folds its delivery in."""

from __future__ import annotations

from dataclasses import replace

from hypothesis import given, settings
from hypothesis import strategies as st

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.control import DeliverySettings, DeliveryTracker
from uma.engine.rate import UmaRate
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


def make_rate() -> UmaRate:
    return UmaRate(EngineConfig(estimator=EstimatorConfig(initial_kbps=300.0)), FeedbackConfig())


def deliveries(count: int, rate_kbps: float):
    """`count` 100 ms intervals of a link at `rate_kbps`: frames of 4 packets every 40 ms."""
    tracker = DeliveryTracker(DeliverySettings(interval_ms=None))
    out, seq, free_ms = [], 0, 0.0
    for interval in range(count):
        for frame in range(3):
            send_ms = interval * 100.0 + frame * 40.0
            for _ in range(4):
                free_ms = max(free_ms, send_ms) + 9600 / rate_kbps
                tracker.on_packet(seq, send_ms, free_ms + 20.0, 9600)
                seq += 1
        out.append(tracker.flush((interval + 1) * 100.0 + 20.0))
    return out


def reports_of(delivered):
    totals, out, earlier = (0, 0, 0), [], []
    for seq, d in enumerate(delivered):
        report, totals = numbered(
            seq, d.received_bits, d.packets, d.lost, totals, delivery=d, earlier=tuple(earlier)
        )
        out.append(report)
        earlier = (earlier + [(seq, d)])[-8:]
    return out


def test_uma_folds_a_lost_reports_delivery_in_as_if_it_had_come():
    reports = reports_of(deliveries(6, 600.0))
    every, gapped = make_rate(), make_rate()
    for i, report in enumerate(reports):
        every.on_report(report, 0.1 * (i + 1) + 0.02)
        if i not in (2, 3):
            gapped.on_report(report, 0.1 * (i + 1) + 0.02)
    assert gapped.controller.capacity_kbps == every.controller.capacity_kbps
    assert gapped.controller.received_kbps == every.controller.received_kbps
    assert abs(gapped.state.received_kbps - every.state.received_kbps) < 1e-6
    blind = make_rate()  # the same reports, unnumbered: the lost deliveries stay unseen
    for i, report in enumerate(reports):
        if i not in (2, 3):
            plain = ReceiverReport(*[getattr(report, f) for f in ReceiverReport.__match_args__[:7]],
                                   delivery=report.delivery)  # fmt: skip
            blind.on_report(plain, 0.1 * (i + 1) + 0.02)
    assert blind.controller.capacity_kbps != every.controller.capacity_kbps


def test_uma_drops_a_report_older_than_one_seen():
    reports = reports_of(deliveries(4, 600.0))
    rate = make_rate()
    rate.on_report(reports[0], 0.12)
    rate.on_report(reports[2], 0.32)
    before = (rate.controller.capacity_kbps, rate.state, rate.last_report)
    assert rate.on_report(reports[1], 0.33) == (None, [])
    assert (rate.controller.capacity_kbps, rate.state, rate.last_report) == before


def test_uma_does_not_fold_the_old_paths_deliveries_into_a_handover():
    reports = reports_of(deliveries(6, 600.0))
    # LTE has no prior: what the controller holds after the handover is what it measured
    named = [replace(r, technology="WLAN" if i < 4 else "LTE") for i, r in enumerate(reports)]
    folded, unnumbered = make_rate(), make_rate()
    for i, report in enumerate(named):
        if i in (2, 3):
            continue  # lost: report 4 names LTE and repeats them
        folded.on_report(report, 0.1 * (i + 1) + 0.02)
        unnumbered.on_report(replace(report, seq=-1), 0.1 * (i + 1) + 0.02)
    assert folded.controller.capacity_kbps == unnumbered.controller.capacity_kbps
