"""Messages the receiver sends the engine over the mobile uplink, and what a lost one held.

Units: times in seconds (`_s`), delays in milliseconds (`_ms`), sizes in bits (`_bits`).

Reports are numbered (`ReceiverReport.seq`) and carry cumulative counters since the receiver
started (RTCP-style: the extended highest sequence number, and the bits, packets received and
packets lost), so the first report the sender sees after lost ones tells what they held
(`report_gap`, `span_since`): the received rate over the true interval, a gap that is known.
The deliveries of the last few reports ride along too (`earlier`), so a controller can fold in
the packet trains a lost report carried.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from uma.control.delivery import DeliveryReport

__all__ = ["ReceiverReport", "KeyframeRequest", "ReportGap", "report_gap", "span_since"]


@dataclass(frozen=True)
class ReceiverReport:
    """What the receiver saw since its previous report (RTCP receiver-report style).

    `queue_delay_ms` is the mean one-way delay of the packets received in the interval minus the
    smallest one-way delay seen in the recent past: it grows when a queue builds at the
    bottleneck. It is None when no packet arrived in the interval. `technology` is the access
    technology the receiver is on ("" when it does not say). `delivery`: every packet that
    arrived in the interval, with its send stamp and arrival time, folded by the receiver's
    `DeliveryTracker` (trains, loss, queueing-delay samples); the rate controllers read it.

    `seq` numbers the receiver's reports from 0 (-1: unnumbered); `total_bits`,
    `total_packets` and `total_lost` are cumulative since the receiver started, this report
    included (-1: not given). `earlier`: (seq, delivery) of the last few earlier reports whose
    delivery held packets, oldest first.
    """

    sent_s: float
    interval_s: float
    received_bits: int
    packets_received: int
    packets_lost: int
    highest_seq: int
    queue_delay_ms: float | None
    description_complete: bool = False  # the receiver holds the whole content description
    technology: str = ""
    refresh_frame: int = -1  # the newest model-aided refresh the receiver renders from
    delivery: DeliveryReport | None = None
    seq: int = -1
    total_bits: int = -1
    total_packets: int = -1
    total_lost: int = -1
    earlier: tuple[tuple[int, DeliveryReport], ...] = ()

    @property
    def received_kbps(self) -> float:
        return self.received_bits / self.interval_s / 1000.0 if self.interval_s > 0 else 0.0

    @property
    def loss_fraction(self) -> float:
        total = self.packets_received + self.packets_lost
        return self.packets_lost / total if total else 0.0

    @property
    def numbered(self) -> bool:
        """Whether the report carries its number and the cumulative counters."""
        return self.seq >= 0 and min(self.total_bits, self.total_packets, self.total_lost) >= 0


@dataclass(frozen=True)
class ReportGap:
    """What lay between the last report seen and this one: `missed` reports lost on the way,
    holding `bits`, `packets` received and `lost` packets. `stale`: this report is not newer
    than the last seen (reordered or repeated); nothing of it is new."""

    missed: int = 0
    bits: int = 0
    packets: int = 0
    lost: int = 0
    stale: bool = False


def report_gap(last: ReceiverReport | None, report: ReceiverReport) -> ReportGap:
    """The reports lost between `last` (the newest seen; None: none yet) and `report`, from
    their numbers and cumulative counters; an empty gap when either is unnumbered. A
    receiver's counters never fall, but a negative difference (a corrupt report) counts 0."""
    if last is None or not (last.numbered and report.numbered):
        return ReportGap()
    if report.seq <= last.seq:
        return ReportGap(stale=True)
    return ReportGap(
        missed=report.seq - last.seq - 1,
        bits=max(report.total_bits - last.total_bits - report.received_bits, 0),
        packets=max(report.total_packets - last.total_packets - report.packets_received, 0),
        lost=max(report.total_lost - last.total_lost - report.packets_lost, 0),
    )


def span_since(last: ReceiverReport | None, report: ReceiverReport) -> ReceiverReport:
    """`report` widened to everything since `last`: the interval from `last`'s sending, the
    bits and packets of the reports lost between them added. `report` itself when none was
    lost (or when it is stale or unnumbered)."""
    gap = report_gap(last, report)
    if last is None or gap.stale or not gap.missed:
        return report
    return replace(
        report,
        interval_s=max(report.sent_s - last.sent_s, report.interval_s),
        received_bits=report.received_bits + gap.bits,
        packets_received=report.packets_received + gap.packets,
        packets_lost=report.packets_lost + gap.lost,
    )


@dataclass(frozen=True)
class KeyframeRequest:
    """The receiver lost a reference frame and asks for an IDR (an RTCP PLI); `refresh`: a
    model-aided refresh was lost or undecodable, and the next refresh should be intra."""

    sent_s: float
    frame: int
    refresh: bool = False
