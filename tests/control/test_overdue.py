"""The overdue packet in a report with packets (`overdue_in_any_report`, off by default)."""

from __future__ import annotations

import pytest

from uma.control import UmaController, UmaSettings
from uma.control.delivery import DeliveryReport, PacketRecord


def _arrived(send_ms, arrival_ms, end_ms, *, bits=9600):
    """A report of one packet sent at `send_ms` that met no queue (the path's base delay)."""
    record = PacketRecord(0, send_ms, arrival_ms, bits)
    return DeliveryReport(
        start_ms=end_ms - 100.0, end_ms=end_ms, packets=1, received_bits=bits, lost=0,
        train_bits=0, train_ms=0.0, queue_delay_ms=(0.0,), records=(record,),
    )  # fmt: skip


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
    quiet) is no outage yet: a probe either way."""
    settings = UmaSettings(initial_kbps=300.0, no_probe_into_silence=into_silence)
    controller = UmaController(settings)
    controller.on_report(_arrived(0.0, 20.0, 100.0))
    probe = controller.on_report(_empty(1000.0, 1100.0), due=due).probe
    assert (probe is None) is (into_silence and due == (790.0, 9600))
