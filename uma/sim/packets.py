"""What travels on the downlink: encoded frames ("units") cut into packets.

Units: sizes in bits and bytes as named, times in seconds.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "EncodedUnit",
    "Packet",
    "packetize",
    "packet_sizes_bits",
    "padding_packets",
    "padding_sizes_bits",
    "HEADER_BYTES",
]

# IPv4 + UDP + RTP headers on every packet.
HEADER_BYTES = 40


@dataclass(frozen=True)
class EncodedUnit:
    """One encoded frame as the engine sends it; `unit_seq` counts sent units without gaps,
    so the receiver can tell a lost unit (and a broken reference chain) from a skipped frame."""

    unit_seq: int
    frame: int
    codec: str
    rung: int
    width: int
    height: int
    keyframe: bool
    data: bytes
    frames: tuple[int, ...] = ()  # every frame the unit carries when several (MBC packets)
    # A model-aided refresh (`uma.sim.refresh`): its own chain, `unit_seq` counts refreshes.
    refresh: bool = False


@dataclass(frozen=True)
class Packet:
    """One packet on the downlink; `unit` is None for a padding-only packet (RTP padding) and
    for a chunk of the content description (`chunk` >= 0: its index of `count` chunks)."""

    seq: int
    unit: EncodedUnit | None
    index: int
    count: int
    size_bits: int
    sent_s: float
    chunk: int = -1


def packetize(
    unit: EncodedUnit, *, first_seq: int, payload_bytes: int, sent_s: float
) -> list[Packet]:
    """Cut `unit` into packets of at most `payload_bytes` of payload plus headers."""
    sizes = packet_sizes_bits(unit, payload_bytes=payload_bytes)
    return [
        Packet(
            seq=first_seq + index,
            unit=unit,
            index=index,
            count=len(sizes),
            size_bits=size,
            sent_s=sent_s,
        )
        for index, size in enumerate(sizes)
    ]


def packet_sizes_bits(unit: EncodedUnit, *, payload_bytes: int) -> list[int]:
    """The packet sizes `packetize` would produce, before sequence numbers are known."""
    size = max(1, len(unit.data))
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


def padding_packets(sizes_bits: list[int], *, first_seq: int, sent_s: float) -> list[Packet]:
    """Padding-only packets of the given sizes, numbered from `first_seq`."""
    return [
        Packet(
            seq=first_seq + i,
            unit=None,
            index=i,
            count=len(sizes_bits),
            size_bits=size,
            sent_s=sent_s,
        )
        for i, size in enumerate(sizes_bits)
    ]
