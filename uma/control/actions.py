"""What a rate controller asks of the sender: a target rate and, at times, a probe.

Units: kbit/s, ms, bits. Controllers return these; they never call back or write shared state.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["ProbeRequest", "RateDecision"]


@dataclass(frozen=True)
class ProbeRequest:
    """Send `packets` padding packets of `packet_bits` back to back (one train, one send stamp).

    Their arrival spacing measures the link (`DeliveryReport.capacity_kbps`) even when the
    video alone does not fill it. `rate_kbps` is the rate the probe asks the link to show.
    """

    rate_kbps: float
    packets: int
    packet_bits: int


@dataclass(frozen=True)
class RateDecision:
    target_kbps: float
    probe: ProbeRequest | None = None
    reason: str = ""
