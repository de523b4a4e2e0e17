"""The engine's bookkeeping of the downlink: bits in flight, and when reports last came.

Units: times in seconds, sizes in bits.

Every packet handed to the downlink gets the next sequence number and its size is added to a
running total; a receiver report's highest sequence number says how much of that arrived.
The bits sent after it are in flight. A report cannot acknowledge more than was sent (a
corrupt or forged one would otherwise index past the sent packets), and packets still
unacknowledged `presume_lost_s` after the last progress are presumed lost: a lost tail would
otherwise look outstanding forever and stall the engine.
"""

from __future__ import annotations

__all__ = ["InFlight", "Keyframes"]


class Keyframes:
    """Keyframe requests: one is pending until an IDR really left, and IDRs keep `min_gap_s`
    apart (a frame the engine could not code never settles a request)."""

    def __init__(self, min_gap_s: float) -> None:
        self.min_gap_s = min_gap_s
        self.pending = False
        self.last_idr_s = float("-inf")

    def request(self) -> None:
        self.pending = True

    def sent(self, now_s: float) -> None:
        self.pending = False
        self.last_idr_s = now_s

    def due(self, now_s: float) -> bool:
        return self.pending and now_s - self.last_idr_s >= self.min_gap_s


class InFlight:
    """Sequence numbers, bits in flight, and the times of the last report and progress."""

    def __init__(self) -> None:
        self.cum_sent_bits: list[int] = [0]  # cum_sent_bits[seq + 1] = bits sent up to seq
        self.sent_s: list[float] = []  # sent_s[seq]: when packet seq was handed to the downlink
        self.highest_seq = -1
        self.last_progress_s = 0.0
        self.last_report_s = 0.0
        self.last_stale_s = 0.0  # when stale reports last lowered the estimate

    def on_report(self, highest_seq: int, now_s: float) -> None:
        """A report arrived at `now_s` naming `highest_seq` as the highest packet received."""
        reported_seq = min(highest_seq, len(self.cum_sent_bits) - 2)
        if reported_seq > self.highest_seq:
            self.highest_seq = reported_seq
            self.last_progress_s = now_s
        self.last_report_s = now_s

    def on_sent(self, sizes_bits, now_s: float) -> int:
        """Packets of `sizes_bits` handed to the downlink at `now_s`; returns the first one's
        number."""
        first_seq = len(self.cum_sent_bits) - 1
        total = self.cum_sent_bits[-1]
        for size in sizes_bits:
            total += size
            self.cum_sent_bits.append(total)
            self.sent_s.append(now_s)
        return first_seq

    def oldest_outstanding(self) -> tuple[float, int] | None:
        """(when it was sent in s, its size in bits) of the first packet after the highest
        reported one; None when every packet sent is reported."""
        seq = self.highest_seq + 1
        if seq >= len(self.sent_s):
            return None
        return self.sent_s[seq], self.cum_sent_bits[seq + 1] - self.cum_sent_bits[seq]

    @property
    def outstanding_bits(self) -> int:
        """Bits sent after the highest sequence number the receiver has reported."""
        return self.cum_sent_bits[-1] - self.cum_sent_bits[self.highest_seq + 1]

    def stale_due(self, now_s: float, interval_s: float, stale_reports: int) -> bool:
        """Whether reports have been missing for `stale_reports` intervals and the estimate
        was not lowered for that within the last interval (then it counts as lowered now)."""
        if now_s - self.last_report_s <= stale_reports * interval_s:
            return False
        if now_s - self.last_stale_s < interval_s:
            return False
        self.last_stale_s = now_s
        return True

    def presume_lost(self, now_s: float, after_s: float) -> None:
        """Take everything as arrived when nothing progressed for `after_s`."""
        if self.outstanding_bits and now_s - self.last_progress_s > after_s:
            self.highest_seq = len(self.cum_sent_bits) - 2
            self.last_progress_s = now_s
