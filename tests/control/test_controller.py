"""uma's controller: bursty delivery is capacity, a handover's prior, an app-limited recovery."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uma.control import DeliveryTracker, UmaController, UmaSettings, should_skip
from uma.control.delivery import DeliveryReport, PacketRecord
from uma.control.skip import frame_budget_bits

PACKET_BITS = 9600
HEADER_BITS = 320


def _frame(rate_kbps: float) -> list[int]:
    bits = rate_kbps * 40.0
    count = max(1, math.ceil(bits / PACKET_BITS))
    return [int(bits / count) + HEADER_BITS] * count


def _loop(controller, capacity_kbps, *, seconds, app_max_kbps=1e9, scheduler=False):
    """A sender at the controller's target (25 frames/s), 20 ms each way, over a FIFO whose
    capacity follows `capacity_kbps(t_ms)`; with `scheduler`, the link delivers what its
    capacity allows only at 40 ms slot boundaries, in one clump. Returns per-frame
    (time_ms, target_kbps, queue_ms) and the probes asked for."""
    tracker = DeliveryTracker()
    target, probe = controller.target_kbps, None
    pending, queue, rows, probes = [], [], [], 0
    free_ms, credit_bits, seq = 0.0, 0.0, 0
    for f in range(int(seconds * 25)):
        now = 40.0 * f
        pending.sort()
        while pending and pending[0][0] <= now:
            _, target, request = pending.pop(0)
            probe = request or probe
        sizes = _frame(min(target, app_max_kbps))
        if probe is not None:
            sizes += [probe.packet_bits] * probe.packets
            probes, probe = probes + 1, None
        arrivals = []
        if scheduler:
            queue += [(now + 1.0, bits) for bits in sizes]
            credit_bits += capacity_kbps(now) * 40.0
            while queue and queue[0][1] <= credit_bits:
                send, bits = queue.pop(0)
                credit_bits -= bits
                arrivals.append((send, now + 40.0 + 20.0 + 0.01 * len(arrivals), bits))
            if not queue:
                credit_bits = min(credit_bits, 0.0)  # an idle link stores no credit
        else:
            for bits in sizes:
                free_ms = max(free_ms, now) + bits / capacity_kbps(now)
                arrivals.append((now, free_ms + 20.0, bits))
        for send, arrival, bits in arrivals:
            report = tracker.on_packet(seq, send, arrival, bits)
            seq += 1
            if report is not None:
                decision = controller.on_report(report)
                pending.append((arrival + 20.0, decision.target_kbps, decision.probe))
        backlog = sum(b for _, b in queue) if scheduler else max(0.0, free_ms - now) * 1.0
        rows.append((now, target, backlog))
    return rows, probes


def test_clumped_delivery_reads_as_capacity_not_as_queue_growth():
    controller = UmaController()
    rows, _ = _loop(controller, lambda t: 1000.0, seconds=30, scheduler=True)
    late = [target for t, target, _ in rows if t > 10_000]
    # it hunts around the link's mean rate (a clump's packets alone read fast, a queue's
    # spans read the mean) and never collapses as if a queue kept building
    assert min(late) > 0.6 * 1000.0
    assert 0.8 * 1000.0 < float(np.median(late)) < 1.05 * 1000.0
    assert max(backlog for t, _, backlog in rows if t > 10_000) < 150.0 * 1000.0  # < 150 ms


def test_a_steady_fifo_is_followed_with_headroom():
    controller = UmaController()
    rows, _ = _loop(controller, lambda t: 600.0, seconds=20)
    late = [target for t, target, _ in rows if t > 10_000]
    assert min(late) > 0.75 * 600 and max(late) <= 0.9 * 600


def test_a_handover_prior_lowers_the_estimate_at_once():
    controller = UmaController()
    _loop(controller, lambda t: 2000.0, seconds=10)
    decision = controller.on_handover("GPRS", 10_000.0)
    assert decision.target_kbps == pytest.approx(40.0 * 0.85)
    assert decision.reason == "handover prior"


def test_a_handover_prior_never_raises_the_estimate_and_unknown_labels_change_nothing():
    controller = UmaController()
    _loop(controller, lambda t: 100.0, seconds=10)
    before = controller.capacity_kbps
    assert controller.on_handover("3G", 10_000.0).target_kbps == pytest.approx(before * 0.85)
    assert controller.on_handover("no-such-technology", 10_040.0).reason == "handover"
    assert controller.capacity_kbps == before


def _dip(t_ms: float) -> float:
    return 30.0 if 5_000 <= t_ms < 10_000 else 1500.0


def test_an_application_limited_stream_measures_its_way_back_up_after_a_dip():
    # the encoder never needs more than 200 kbit/s: one packet a frame, no trains of its own
    controller = UmaController()
    rows, probes = _loop(controller, _dip, seconds=16, app_max_kbps=200.0)
    assert min(target for t, target, _ in rows if 8_000 <= t < 10_000) < 60.0  # it followed
    assert probes > 0
    assert controller.capacity_kbps > 400.0  # measured the link again
    assert all(target > 200.0 for t, target, _ in rows if t > 15_000)  # the stream is whole


def test_without_probes_the_same_stream_stays_low():
    controller = UmaController(UmaSettings(probe_interval_ms=1e9))
    rows, _ = _loop(controller, _dip, seconds=16, app_max_kbps=200.0)
    assert controller.capacity_kbps < 200.0
    assert all(target < 200.0 for t, target, _ in rows if t > 15_000)


def test_silence_cuts_the_estimate_once_per_interval():
    controller = UmaController()
    _loop(controller, lambda t: 1000.0, seconds=5)
    last = controller._quiet_since_ms
    before = min(controller.capacity_kbps, controller.received_kbps)  # the stream's headroom
    assert controller.on_silence(last + 200.0).reason == ""
    assert controller.on_silence(last + 250.0).reason == "silence"
    assert controller.capacity_kbps == pytest.approx(before * 0.25)
    assert controller.on_silence(last + 400.0).reason == ""  # once per `silence_ms`
    assert controller.on_silence(last + 500.0).reason == "silence"


def test_the_sender_pauses_after_one_and_a_half_report_intervals_without_a_report():
    controller = UmaController()
    assert not controller.paused(1e6)  # no report yet: nothing to miss
    controller.on_report(_report(0.0, 100.0))
    assert not controller.paused(249.0)
    assert controller.paused(250.0)  # 150 ms after the report's end
    controller.on_silence(350.0)  # the silence does not reset the pause
    assert controller.paused(400.0)
    controller.on_report(_report(100.0, 420.0))
    assert not controller.paused(420.0)


def _report(start_ms, end_ms, *, bits=40_000, queue_ms=(2.0,), lost=0):
    """A report of `len(queue_ms)` packets (their queueing delays) and `bits` over its span."""
    from uma.control.delivery import DeliveryReport

    return DeliveryReport(
        start_ms=start_ms, end_ms=end_ms, packets=len(queue_ms), received_bits=bits,
        lost=lost, train_bits=0, train_ms=0.0, queue_delay_ms=tuple(queue_ms), records=(),
    )  # fmt: skip


def test_an_application_limited_stream_is_cut_from_what_arrived():
    """Capacity 2,000 kbit/s measured, 400 kbit/s arriving: a silence cuts from the 400."""
    controller = UmaController(UmaSettings(initial_kbps=2000.0))
    for k in range(20):  # 40,000 bits per 100 ms: 400 kbit/s
        controller.on_report(_report(100.0 * k, 100.0 * (k + 1)))
    assert controller.received_kbps == pytest.approx(400.0)
    decision = controller.on_silence(2000.0 + 250.0)
    assert controller.capacity_kbps == pytest.approx(100.0)  # 400 x 0.25
    assert decision.target_kbps == pytest.approx(85.0)


@pytest.mark.parametrize(
    "queue_ms, lost, restored",
    [
        ((2.0, 3.0), 0, True),
        ((2.0, 400.0), 0, True),
        ((250.0, 400.0), 0, False),
        ((2.0,), 1, False),
    ],
)
def test_a_silence_the_next_report_shows_spurious_is_undone(queue_ms, lost, restored):
    """A lost report (the next one's packets met no queue, none lost) is not an outage: the
    cut is undone. Packets that queued through the silence, or a loss, keep it."""
    controller = UmaController(UmaSettings(initial_kbps=400.0))
    for k in range(5):
        controller.on_report(_report(100.0 * k, 100.0 * (k + 1)))
    before = controller.capacity_kbps
    controller.on_silence(750.0)
    assert controller.capacity_kbps == pytest.approx(before * 0.25)
    controller.on_report(_report(650.0, 700.0, bits=0, queue_ms=()))  # nothing arrived: no word
    assert controller.capacity_kbps == pytest.approx(before * 0.25)
    controller.on_report(_report(700.0, 800.0, queue_ms=queue_ms, lost=lost))
    assert (controller.capacity_kbps == pytest.approx(before)) is restored


def test_skip_rule():
    # 100 kbit/s = 100 bits per ms: 40,000 bits drain in 400 ms
    assert frame_budget_bits(20_000, 100.0, 400.0) == 20_000
    assert not should_skip(20_000, 20_000, 100.0, 400.0)
    assert should_skip(20_001, 20_000, 100.0, 400.0)
    assert should_skip(1, 0, 0.0, 400.0)


@pytest.mark.parametrize(
    "field, value", [("headroom", 0.0), ("silence_factor", 1.5), ("probe_packets", 1)]
)
def test_settings_refuse_bad_values_naming_them(field, value):
    with pytest.raises(ValueError, match=field):
        UmaSettings(**{field: value})


@pytest.mark.parametrize("capacity_kbps", [9.6, 40.0, 100.0, 1000.0])
def test_a_probe_queues_about_fifty_ms_even_on_a_slow_link(capacity_kbps):
    """A probe is a train (two packets at least) of about `probe_ms` at the capacity: on GSM's
    9.6 kbit/s five 100-byte packets would have held the link for 0.4 s."""
    controller = UmaController(UmaSettings(initial_kbps=capacity_kbps, min_kbps=1.0))
    probe = controller.on_report(_report(0.0, 100.0, bits=0, queue_ms=())).probe
    assert probe is not None
    assert 2 <= probe.packets <= 5
    queue_ms = probe.packets * probe.packet_bits / capacity_kbps
    # the floor: two packets of 60 bytes (40 of headers) on the slowest link
    assert queue_ms <= max(50.0 * 1.01, 2 * 480 / capacity_kbps)
    if capacity_kbps >= 100.0:
        assert probe.packets == 5 and queue_ms == pytest.approx(50.0, rel=0.05)


def test_one_quiet_clock_times_the_pause_and_each_silence_and_a_report_restarts_it():
    """The pause and the silences count from the last report's end alone: cuts at 250, 500 and
    750 ms of quiet however late `on_silence` is asked within each, the pause all along; the
    next report ends both."""
    controller = UmaController(UmaSettings(initial_kbps=400.0))
    controller.on_report(_report(0.0, 100.0))
    assert controller.quiet_ms(340.0) == pytest.approx(240.0)
    reasons = [controller.on_silence(t).reason for t in (340.0, 390.0, 420.0, 600.0, 640.0)]
    assert reasons == ["", "silence", "", "silence", ""]  # at 250 and 500 ms of quiet
    assert controller.on_silence(850.0).reason == "silence"  # 750 ms
    assert controller.paused(850.0)
    controller.on_report(_report(100.0, 900.0, queue_ms=(300.0,)))
    assert not controller.paused(900.0) and controller.quiet_ms(900.0) == 0.0
    assert controller.on_silence(1100.0).reason == ""  # 200 ms of quiet: none yet
    assert controller.on_silence(1150.0).reason == "silence"


def _arrived(send_ms, arrival_ms, end_ms, *, bits=9600):
    """A report of one packet sent at `send_ms` that met no queue (the path's base delay)."""
    record = PacketRecord(0, send_ms, arrival_ms, bits)
    return DeliveryReport(
        start_ms=end_ms - 100.0, end_ms=end_ms, packets=1, received_bits=bits, lost=0,
        train_bits=0, train_ms=0.0, queue_delay_ms=(0.0,), records=(record,),
    )  # fmt: skip


@pytest.mark.parametrize("due", [None, (150.0, 9600), (90.0, 9600)])
def test_an_empty_report_while_a_packet_was_due_is_no_news_from_the_link(due):
    """Reports keep coming but the link delivers nothing: the packet sent at 90 ms should
    have arrived at 90 + 20 (base) + 9,600 bits / 300 kbit/s = 142 ms; the report ending at
    200 ms holds nothing, so the link has been quiet since 142 ms: 58 ms overdue pauses the
    sender (>= 50 ms), and the silence cuts at 142 + 250 ms. One sent at 150 ms was not due
    yet (202 ms); with nothing outstanding an empty report is the usual news."""
    controller = UmaController(UmaSettings(initial_kbps=300.0))
    controller.on_report(_arrived(0.0, 20.0, 100.0))
    empty = _report(100.0, 200.0, bits=0, queue_ms=())
    controller.on_report(empty, due=due)
    overdue = due == (90.0, 9600)
    assert controller.quiet_ms(200.0) == pytest.approx(58.0 if overdue else 0.0)
    assert controller.paused(200.0) is overdue
    assert (controller.on_silence(392.0).reason == "silence") is overdue
    controller.on_report(_arrived(90.0, 400.0, 400.0))  # it came: news again
    assert not controller.paused(400.0)


# The overdue packet in a report with packets and the probes it stops (keys off by default).
@pytest.mark.parametrize("any_report", [False, True])
@pytest.mark.parametrize("due", [None, (200.0, 9600), (90.0, 9600)])
def test_a_packet_overdue_after_the_last_arrival_counts_in_a_report_with_packets(any_report, due):
    """The report ending at 200 ms holds the packet sent at 100 ms (arrived 120 ms); the one
    sent at 90 ms is still out: due at max(90 + 20, 120) + 9,600 bits / 300 kbit/s = 152 ms,
    58 ms (over the 50 ms grace) before the report's end at 210 ms. With the key the quiet
    clock runs from 152 ms and the sender pauses; without it, with nothing outstanding, or
    with the packet sent at 200 ms (due at 252 ms) the report is news as ever."""
    controller = UmaController(UmaSettings(initial_kbps=300.0, overdue_in_any_report=any_report))
    controller.on_report(_arrived(0.0, 20.0, 100.0))
    controller.on_report(_arrived(100.0, 120.0, 210.0), due=due)
    counted = any_report and due == (90.0, 9600)
    assert controller.quiet_ms(210.0) == pytest.approx(58.0 if counted else 0.0)
    assert controller.paused(210.0) is counted
    assert (controller.on_silence(152.0 + 250.0).reason == "silence") is counted
    controller.on_report(_arrived(90.0, 420.0, 420.0))  # it came: news again
    assert not controller.paused(420.0)


def _empty(start_ms, end_ms):
    return DeliveryReport(
        start_ms=start_ms, end_ms=end_ms, packets=0, received_bits=0, lost=0,
        train_bits=0, train_ms=0.0, queue_delay_ms=(), records=(),
    )  # fmt: skip


@pytest.mark.parametrize("no_probe", [False, True])
@pytest.mark.parametrize("due", [None, (1150.0, 9600), (1040.0, 9600)])
def test_no_probe_into_a_link_that_owes_a_packet(no_probe, due):
    """Unmeasured for a second, an empty report (application-limited): a probe, unless the
    key is on and the packet sent at 1,040 ms was due (at 1,092 ms) before the report's end
    (1,100 ms); one sent at 1,150 ms is not due yet, and with nothing out there is no debt."""
    controller = UmaController(UmaSettings(initial_kbps=300.0, no_probe_while_owed=no_probe))
    controller.on_report(_arrived(0.0, 20.0, 100.0))
    probe = controller.on_report(_empty(1000.0, 1100.0), due=due).probe
    assert (probe is None) is (no_probe and due == (1040.0, 9600))


@pytest.mark.parametrize("into_silence", [False, True])
@pytest.mark.parametrize("due", [(1040.0, 9600), (790.0, 9600)])
def test_no_probe_once_the_link_has_been_quiet_for_a_silence(into_silence, due):
    """The packet sent at 790 ms was due at 842 ms: by the empty report's end (1,100 ms) the
    link has been quiet 258 ms, a silence's worth (250): with the key no probe (the cut comes
    first), without it a probe sized on the old estimate. One due at 1,092 ms (8 ms of
    quiet) is no outage yet: a probe either way. (The pause's own rule, on by default, would
    stop that probe too: off here, so the test judges this key alone.)"""
    settings = UmaSettings(
        initial_kbps=300.0, no_probe_into_silence=into_silence, no_probe_while_paused=False
    )
    controller = UmaController(settings)
    controller.on_report(_arrived(0.0, 20.0, 100.0))
    probe = controller.on_report(_empty(1000.0, 1100.0), due=due).probe
    assert (probe is None) is (into_silence and due == (790.0, 9600))


@pytest.mark.parametrize("while_paused", [False, True])
@pytest.mark.parametrize("due", [None, (1040.0, 9600), (790.0, 9600)])
def test_no_probe_while_the_sender_is_paused(while_paused, due):
    """Unmeasured for a second, an empty report: the packet sent at 790 ms was due at 842 ms,
    258 ms before the report's end, so the sender is paused (overdue): with the key no probe.
    One due at 1,092 ms (8 ms) does not pause, nor does nothing outstanding: a probe."""
    settings = UmaSettings(initial_kbps=300.0, no_probe_while_paused=while_paused)
    controller = UmaController(settings)
    controller.on_report(_arrived(0.0, 20.0, 100.0))
    probe = controller.on_report(_empty(1000.0, 1100.0), due=due).probe
    assert controller.paused(1100.0) is (due == (790.0, 9600))
    assert (probe is None) is (while_paused and due == (790.0, 9600))


@pytest.mark.parametrize("fixed", [False, True])
def test_a_silence_cut_does_not_move_an_overdue_packet_s_due_time(fixed):
    """The packet sent at 790 ms was due at 842 ms (9,600 bits at 300 kbit/s); at 1,100 ms the
    silence cuts the estimate to about 20 kbit/s. Timed at the cut estimate the same packet
    would take 488 ms and seem due only at 1,298 ms: the next empty report (1,200 ms) would
    restart the quiet clock and end the pause. With `fixed_due_time` its due time stays."""
    controller = UmaController(UmaSettings(initial_kbps=300.0, fixed_due_time=fixed))
    controller.on_report(_arrived(0.0, 20.0, 100.0))
    controller.on_report(_empty(1000.0, 1100.0), due=(790.0, 9600))
    assert controller.on_silence(1100.0).reason == "silence"
    assert controller.capacity_kbps < 25.0
    controller.on_report(_empty(1100.0, 1200.0), due=(790.0, 9600))
    assert controller.paused(1200.0) is fixed
    assert controller.quiet_ms(1200.0) == pytest.approx(358.0 if fixed else 0.0)
