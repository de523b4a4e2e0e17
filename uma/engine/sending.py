"""The engine's one send path: packets cut, queued in the pacer, numbered as they leave.

Units: times in seconds, rates in kbit/s, sizes in bits or bytes as named.

Every packet the engine sends leaves through `Outbox`: a coded unit is cut into packets of at
most `payload_bytes` of payload plus `HEADER_BYTES` of IPv4 + UDP + RTP headers
(`packet_sizes_bits`), padding into padding-only packets (`padding_sizes_bits`); units and
padding wait in the pacer (`uma.engine.pacer`), and `number` gives each packet that leaves
its sequence number, the only place sequence numbers are given. Without `engine.pacer` the
pacer runs at an unlimited rate with no deadlines, so what is queued leaves at once. The
content description's chunks and the refresh's packets are paced by their own planners
(`uma.engine.description`, `uma.engine.refresh`) and numbered here as they leave.
"""

from __future__ import annotations

import math
from dataclasses import replace

from uma.engine.decisions import SendPacket, WakePacer
from uma.engine.inflight import InFlight
from uma.engine.pacer import PADDING, PRIORITY, VIDEO, PacedPacket, Pacer, PacerRelease
from uma.engine.records import EngineEvent, Tally

__all__ = [
    "HEADER_BYTES",
    "Outbox",
    "cut",
    "dropped_actions",
    "packet_sizes_bits",
    "padding_sizes_bits",
]

# IPv4 + UDP + RTP headers on every packet.
HEADER_BYTES = 40


def packet_sizes_bits(size_bytes: int, *, payload_bytes: int) -> list[int]:
    """The sizes of the packets a unit of `size_bytes` is cut into (one at least)."""
    size = max(1, size_bytes)
    count = -(-size // payload_bytes)
    return [8 * (min(payload_bytes, size - i * payload_bytes) + HEADER_BYTES) for i in range(count)]


def padding_sizes_bits(bits: float, *, payload_bytes: int) -> list[int]:
    """Sizes of the padding-only packets that carry about `bits` on the wire (headers included)."""
    total_bytes = int(bits // 8)
    if total_bytes <= HEADER_BYTES:
        return []
    full = payload_bytes + HEADER_BYTES
    sizes = [8 * full] * (total_bytes // full)
    rest = total_bytes - full * len(sizes)
    if rest > HEADER_BYTES:
        sizes.append(8 * rest)
    return sizes


def cut(kind: str, payload: object, size_bytes: int, *, payload_bytes: int) -> list[SendPacket]:
    """A unit's packets, not yet numbered (`seq` -1)."""
    sizes = packet_sizes_bits(size_bytes, payload_bytes=payload_bytes)
    return [SendPacket(kind, payload, i, len(sizes), size, -1) for i, size in enumerate(sizes)]


def dropped_actions(frames: tuple[int, ...], now_s: float, why: str) -> list:
    """The count and the event of frames the pacer dropped."""
    if not frames:
        return []
    detail = f"frames {frames[0]}-{frames[-1]}: {why}"
    return [Tally("pacer_dropped_frames", len(frames)), EngineEvent(now_s, "pacer_drop", detail)]


class Outbox:
    """The pacer in front of the downlink and the packets' numbering (bits in flight)."""

    def __init__(self, pacer_config, *, payload_bytes: int, source_fps: float) -> None:
        self.paced = pacer_config.enabled
        self.pacer = Pacer(
            burst_ms=pacer_config.burst_ms, padding_wait_ms=pacer_config.padding_wait_ms
        )
        self.deadline_s = pacer_config.deadline_ms / 1000.0 if self.paced else math.inf
        self.payload_bytes = payload_bytes
        self.source_fps = source_fps
        self.inflight = InFlight()
        self.next_unit = 0

    @property
    def queued_bits(self) -> int:
        return self.pacer.queued_bits

    def number(self, packets: list[SendPacket], now_s: float) -> list[SendPacket]:
        """Give `packets` the next sequence numbers; they are in flight from `now_s`."""
        if not packets:
            return []
        first_seq = self.inflight.on_sent([packet.size_bits for packet in packets], now_s)
        return [replace(packet, seq=first_seq + i) for i, packet in enumerate(packets)]

    def unit(
        self, payload: object, size_bytes: int, *, frames: tuple[int, ...], keyframe: bool,
        priority: bool, now_s: float,
    ) -> tuple[list, int]:  # fmt: skip
        """Queue a coded unit: what leaves at once (or `WakePacer`) with the events of units a
        priority unit or a keyframe dropped from the queue, and the unit's bits."""
        unit, self.next_unit = self.next_unit, self.next_unit + 1
        deadline_s = frames[-1] / self.source_fps + self.deadline_s
        packets = [
            PacedPacket(packet, packet.size_bits, unit, frames[-1], deadline_s, keyframe)
            for packet in cut("video", payload, size_bytes, payload_bytes=self.payload_bytes)
        ]
        dropped = self.pacer.push(packets, PRIORITY if priority else VIDEO)
        actions = self._flush(now_s) + dropped_actions(dropped, now_s, "model codec first")
        return actions, sum(packet.size_bits for packet in packets)

    def padding(self, bits: float, now_s: float) -> list:
        """Queue about `bits` of padding: what leaves at once (or `WakePacer`)."""
        sizes = padding_sizes_bits(bits, payload_bytes=self.payload_bytes)
        if not sizes:
            return []
        packets = [
            PacedPacket(SendPacket("padding", None, i, len(sizes), size, -1), size, -1, -1, now_s)
            for i, size in enumerate(sizes)
        ]
        self.pacer.push(packets, PADDING)
        return self._flush(now_s)

    def probe(self, packets: int, packet_bits: int, now_s: float) -> list[SendPacket]:
        """A rate controller's probe: `packets` padding packets of `packet_bits` on the wire,
        numbered and sent now, back to back with one send stamp (not paced: their arrival
        spacing is to measure the link, not the pacer)."""
        bits = max(packet_bits, 8 * (HEADER_BYTES + 1))
        return self.number(
            [SendPacket("padding", None, i, packets, bits, -1) for i in range(packets)], now_s
        )

    def _flush(self, now_s: float) -> list:
        if self.paced:
            return [WakePacer()]
        release = self.pacer.release(now_s, math.inf, network_delay_s=0.0)
        return self.number([packet.payload for packet in release.sent], now_s)

    def release(
        self, now_s: float, rate_kbps: float, *, network_delay_s: float, hold: bool
    ) -> tuple[list[SendPacket], PacerRelease]:
        """What the pacer lets out at `now_s` at `rate_kbps`, numbered, and its release."""
        release = self.pacer.release(now_s, rate_kbps, network_delay_s=network_delay_s, hold=hold)
        return self.number([packet.payload for packet in release.sent], now_s), release
