"""Delivering the model codec's content description ahead of need, and timing the wait for it.

Units: times in seconds, rates in kbit/s, sizes in bits.

The description goes out in chunks sharing the downlink with the video. Each frame interval
earns the larger of (budget - the point's rate) and `share` x budget of credit (the top rung
leaves no room), the whole budget while the model codec is wanted and waits for it; chunks go
out while the credit lasts and, unless the model codec waits, while the bits in flight stay
below half the backlog budget, round and round the description until a receiver report says
it is complete (a lost chunk comes again). The model codec is used only once that report came.
"""

from __future__ import annotations

from uma.engine.decisions import SendPacket
from uma.engine.records import EngineEvent

__all__ = ["Delivery"]


class Delivery:
    """The description's `bits` in `chunks` packets of `chunk_bits` each (0 bits: nothing to
    deliver, or the receiver is assumed to hold it)."""

    def __init__(
        self,
        *,
        bits: int,
        chunks: int,
        chunk_bits: int,
        share: float,
        codec: str,
    ) -> None:
        self.bits = bits
        self.chunks = chunks
        self.chunk_bits = chunk_bits
        self.share = share
        self.codec = codec  # the model codec it is for: its events carry the name
        self.acked_s: float | None = None if bits else 0.0
        self.wait_from_s: float | None = None
        self.wait_s = 0.0
        self.credit_bits = 0.0
        self.next_chunk = 0

    @property
    def pending(self) -> bool:
        """The description still has to reach the receiver."""
        return self.acked_s is None

    def on_report(self, complete: bool, now_s: float) -> list[EngineEvent]:
        if not complete or self.acked_s is not None:
            return []
        self.acked_s = now_s
        self.stop_wait(now_s)
        return [EngineEvent(now_s, "description_delivered", f"{self.bits} bits")]

    def wait(self, now_s: float) -> list[EngineEvent]:
        """The model codec is wanted but the description is not there: count the time."""
        if self.wait_from_s is not None:
            return []
        self.wait_from_s = now_s
        detail = "description not delivered"
        return [EngineEvent(now_s, f"{self.codec}_waiting_description", detail)]

    def stop_wait(self, now_s: float) -> None:
        if self.wait_from_s is not None:
            self.wait_s += now_s - self.wait_from_s
            self.wait_from_s = None

    def wait_until(self, end_s: float) -> float:
        """The whole wait, a wait still open counted to `end_s`."""
        return self.wait_s + (end_s - self.wait_from_s if self.wait_from_s is not None else 0.0)

    def send(
        self,
        *,
        budget_kbps: float,
        point_rate_kbps: float,
        fps: float,
        backlog_bits: float,
        outstanding_bits: int,
    ) -> list[SendPacket]:
        """The chunks to send in this frame interval (not yet numbered), while the credit lasts
        and, unless the model codec waits, the bits in flight (`outstanding_bits`, each chunk
        added as it is chosen) stay below `backlog_bits`."""
        if not self.pending:
            return []
        waiting = self.wait_from_s is not None
        if waiting:
            credit_kbps = budget_kbps  # the model codec waits for it: all the budget
        else:
            credit_kbps = max(budget_kbps - point_rate_kbps, self.share * budget_kbps)
        self.credit_bits += credit_kbps * 1000.0 / fps
        out: list[SendPacket] = []
        while self.credit_bits >= self.chunk_bits and (waiting or outstanding_bits < backlog_bits):
            chunk = self.next_chunk % self.chunks
            out.append(SendPacket("description", None, chunk, self.chunks, self.chunk_bits, -1))
            self.next_chunk += 1
            self.credit_bits -= self.chunk_bits
            outstanding_bits += self.chunk_bits
        return out
