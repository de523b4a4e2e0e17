"""What travels on the downlink: encoded frames ("units") cut into packets.

The cutting itself is the engine's send path's (`uma.engine.sending`); these build the
packets the world offers the downlink.

Units: sizes in bits and bytes as named, times in seconds.
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.engine.sending import HEADER_BYTES, padding_sizes_bits
from uma.engine.sending import packet_sizes_bits as _unit_sizes_bits

__all__ = [
    "EncodedUnit",
    "Packet",
    "packetize",
    "packet_sizes_bits",
    "padding_packets",
    "padding_sizes_bits",
    "HEADER_BYTES",
]


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
    """The packet sizes `packetize` produces (`uma.engine.sending` cuts them)."""
    return _unit_sizes_bits(len(unit.data), payload_bytes=payload_bytes)


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
