"""What the receiver reports about what arrived and when: packet trains, loss, queueing delay.

Units: times in ms (the sender's send stamps and the receiver's arrival times may be on
different clocks: only differences of one-way delays are used), sizes in bits, rates in kbit/s.

The receiver feeds every packet to a `DeliveryTracker` (`on_packet(seq, send_ms, arrival_ms,
size_bits)`); each call returns None, or a frozen `DeliveryReport` once `interval_ms` of arrival
time has passed since the previous report began (the feedback cadence; with `interval_ms`
None only `flush` closes one, as the simulation's receiver does at each of its reports). A report carries:

- **capacity from packet trains.** A packet that reached the bottleneck before the previous
  one had left it queues behind it, so its arrival gap is the link's time to carry it: a
  train. On an idle link a packet would arrive at its send time plus the base one-way delay
  (the smallest of the last `base_window_ms`); when the previous packet arrived later than
  that (less `grace_ms` for clock jitter), this one waited behind it. The sender's own pauses
  are thereby forgiven (Salsify's grace period): a packet sent after a pause belongs to the
  train only if the link was still busy with the ones before. Packets sent in one burst (a
  frame) always queue behind each other, so every multi-packet frame measures the link. A report's
  `capacity_kbps` pools the trains' packets that arrived in it (each but a train's first, over
  its arrival gap: bits over time), so a link that delivers in clumps (cellular
  schedulers) reads as its mean rate over the clumps, not as queue growth.
- **received rate**: bits over the report's arrival span.
- **loss** from sequence gaps (a late packet that fills a gap is not counted lost twice).
- **queueing-delay samples**: each packet's one-way delay minus the smallest one-way delay of
  the last `base_window_ms` (the propagation estimate: a minute, longer than any standing
  queue, or the queue itself would become the base; `on_path_change()` after a handover
  forgets it).
The packets themselves ride along (`records`) for controllers that group them their own way
(the GCC baseline's inter-arrival groups).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

__all__ = ["PacketRecord", "DeliveryReport", "DeliveryTracker", "DeliverySettings"]


@dataclass(frozen=True)
class PacketRecord:
    seq: int
    send_ms: float
    arrival_ms: float
    size_bits: int


@dataclass(frozen=True)
class DeliverySettings:
    """How packets are folded into reports; validated on creation."""

    interval_ms: float | None = 100.0  # None: only `flush` closes a report
    grace_ms: float = 1.0
    base_window_ms: float = 60_000.0

    def __post_init__(self) -> None:
        checked = {"base_window_ms": self.base_window_ms}
        if self.interval_ms is not None:
            checked["interval_ms"] = self.interval_ms
        for name, value in checked.items():
            if not value > 0:
                raise ValueError(f"DeliverySettings.{name}: expected > 0, got {value}")
        if not self.grace_ms >= 0:
            raise ValueError(f"DeliverySettings.grace_ms: expected >= 0, got {self.grace_ms}")


@dataclass(frozen=True)
class DeliveryReport:
    """What arrived over [start_ms, end_ms] of the receiver's clock."""

    start_ms: float
    end_ms: float
    packets: int
    received_bits: int
    lost: int
    train_bits: int  # bits of the packets that queued behind the one before
    train_ms: float  # their arrival gaps, summed
    queue_delay_ms: tuple[float, ...]  # one per packet, in arrival order
    records: tuple[PacketRecord, ...]

    @property
    def received_kbps(self) -> float:
        span_ms = max(self.end_ms - self.start_ms, 1.0)
        return self.received_bits / span_ms

    @property
    def capacity_kbps(self) -> float | None:
        """The trains' pooled rate; None when no packet queued behind another here."""
        return self.train_bits / self.train_ms if self.train_ms > 0 else None

    @property
    def loss_fraction(self) -> float:
        expected = self.packets + self.lost
        return self.lost / expected if expected else 0.0

    @property
    def queue_delay_last_ms(self) -> float | None:
        return self.queue_delay_ms[-1] if self.queue_delay_ms else None


class DeliveryTracker:
    """Folds arrivals into `DeliveryReport`s; one call per packet, in arrival order."""

    def __init__(self, settings: DeliverySettings | None = None) -> None:
        self.settings = settings or DeliverySettings()
        self._records: list[PacketRecord] = []
        self._delays: list[float] = []
        self._start_ms: float | None = None
        self._highest_seq: int | None = None
        self._lost = 0
        self._missing: set[int] = set()
        self._previous: PacketRecord | None = None
        self._pooled_bits = 0
        self._pooled_ms = 0.0
        self._minima: deque[tuple[float, float]] = deque()  # (arrival_ms, one-way delay) rising

    def on_packet(
        self, seq: int, send_ms: float, arrival_ms: float, size_bits: int
    ) -> DeliveryReport | None:
        """Record one arrival; the report when this arrival closes a feedback interval."""
        record = PacketRecord(int(seq), float(send_ms), float(arrival_ms), int(size_bits))
        if self._start_ms is None:
            self._start_ms = record.arrival_ms
        self._count_loss(record.seq)
        delay_ms = self._queue_delay(record)
        self._extend_train(record, base_ms=record.arrival_ms - record.send_ms - delay_ms)
        self._records.append(record)
        self._delays.append(delay_ms)
        self._previous = record
        interval_ms = self.settings.interval_ms
        if interval_ms is not None and record.arrival_ms - self._start_ms >= interval_ms:
            return self.flush(record.arrival_ms)
        return None

    def flush(self, now_ms: float) -> DeliveryReport:
        """The report of everything since the last one."""
        start = self._start_ms if self._start_ms is not None else now_ms
        report = DeliveryReport(
            start_ms=start,
            end_ms=max(now_ms, start),
            packets=len(self._records),
            received_bits=sum(r.size_bits for r in self._records),
            lost=self._lost,
            train_bits=self._pooled_bits,
            train_ms=self._pooled_ms,
            queue_delay_ms=tuple(self._delays),
            records=tuple(self._records),
        )
        self._records, self._delays = [], []
        self._lost, self._pooled_bits, self._pooled_ms = 0, 0, 0.0
        self._start_ms = now_ms
        return report

    def on_path_change(self) -> None:
        """A new path (a handover): its propagation delay is measured afresh."""
        self._minima.clear()

    def _count_loss(self, seq: int) -> None:
        if self._highest_seq is None or seq > self._highest_seq:
            if self._highest_seq is not None and seq > self._highest_seq + 1:
                gap = range(self._highest_seq + 1, seq)
                self._lost += len(gap)
                self._missing.update(gap)
                if len(self._missing) > 10_000:  # forget the oldest gaps
                    self._missing = set(sorted(self._missing)[-5_000:])
            self._highest_seq = seq
        elif seq in self._missing:  # a late packet: not lost after all
            self._missing.discard(seq)
            self._lost -= 1

    def _extend_train(self, record: PacketRecord, *, base_ms: float) -> None:
        """Pool the packet's arrival gap into the trains when it queued behind the previous."""
        previous = self._previous
        if previous is None:
            return
        # On an idle link the packet would have arrived at send + base; if the previous packet
        # arrived later than that, this one waited behind it and the gap is the link's time.
        queued = previous.arrival_ms > record.send_ms + base_ms - self.settings.grace_ms
        arrival_gap = record.arrival_ms - previous.arrival_ms
        if queued and arrival_gap >= 0:
            self._pooled_bits += record.size_bits
            self._pooled_ms += arrival_gap

    def _queue_delay(self, record: PacketRecord) -> float:
        owd = record.arrival_ms - record.send_ms
        window = self.settings.base_window_ms
        while self._minima and self._minima[-1][1] >= owd:
            self._minima.pop()
        self._minima.append((record.arrival_ms, owd))
        while self._minima[0][0] < record.arrival_ms - window:
            self._minima.popleft()
        return owd - self._minima[0][1]
