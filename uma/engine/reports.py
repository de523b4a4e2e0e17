"""Messages the receiver sends the engine over the mobile uplink.

Units: times in seconds (`_s`), delays in milliseconds (`_ms`), sizes in bits (`_bits`).
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.control.delivery import DeliveryReport

__all__ = ["ReceiverReport", "KeyframeRequest"]


@dataclass(frozen=True)
class ReceiverReport:
    """What the receiver saw since its previous report (RTCP receiver-report style).

    `queue_delay_ms` is the mean one-way delay of the packets received in the interval minus the
    smallest one-way delay seen in the recent past: it grows when a queue builds at the
    bottleneck. It is None when no packet arrived in the interval. `technology` is the access
    technology the receiver is on ("" when it does not say). `delivery`: every packet that
    arrived in the interval, with its send stamp and arrival time, folded by the receiver's
    `DeliveryTracker` (trains, loss, queueing-delay samples); the rate controllers read it.
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

    @property
    def received_kbps(self) -> float:
        return self.received_bits / self.interval_s / 1000.0 if self.interval_s > 0 else 0.0

    @property
    def loss_fraction(self) -> float:
        total = self.packets_received + self.packets_lost
        return self.packets_lost / total if total else 0.0


@dataclass(frozen=True)
class KeyframeRequest:
    """The receiver lost a reference frame and asks for an IDR (an RTCP PLI); `refresh`: a
    model-aided refresh was lost or undecodable, and the next refresh should be intra."""

    sent_s: float
    frame: int
    refresh: bool = False
