"""Each part of a run keeps its own tally; the result holds them frozen.

Units: sizes in bits (bytes where the name says), times in seconds.

A new tally is one field here and the line of `uma.sim.summary` that reports it: the world
and the processes add to the mutable tallies `SentBits` and `ModelWork`, the receiver to its
`RefreshReceived`; `uma.sim.result.collect_result` freezes them (`ModelStats`,
`DescriptionStats`, `RefreshStats`) into the `RunResult`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any

__all__ = [
    "SentBits",
    "ModelWork",
    "RefreshReceived",
    "ModelStats",
    "DescriptionStats",
    "RefreshStats",
]


@dataclass
class SentBits:
    """Bits offered to the downlink, headers included, by what the units carry (the codecs'
    own video and parameter bits are in the frame log, not here)."""

    description: int = 0
    refresh: int = 0
    padding: int = 0

    def add(self, kind: str, size_bits: int) -> None:
        """Count a packet of `kind` (a kind without a field here is not tallied)."""
        if kind in _SENT_KINDS:
            setattr(self, kind, getattr(self, kind) + size_bits)


_SENT_KINDS = frozenset(f.name for f in fields(SentBits))


@dataclass
class ModelWork:
    """The model codec's work in the engine while a run goes: the frames its
    initialisations began at, each one's (frame, fitted parameters or None when it failed),
    the engine compute modelled for it (initialisations included) and for its refresh."""

    init_frames: list[int] = field(default_factory=list)
    inits: list[tuple[int, Any]] = field(default_factory=list)
    compute_s: float = 0.0
    refresh_compute_s: float = 0.0


@dataclass
class RefreshReceived:
    """The refreshes the receiver decoded, and those it saw lost or could not decode."""

    decoded: int = 0
    lost: int = 0


@dataclass(frozen=True)
class ModelStats:
    """The model codec's work in a finished run; with the selection scheme, also the
    parameter bits the sender sent up and its modelled tracking compute."""

    init_frames: tuple[int, ...] = ()
    inits: tuple = ()
    engine_compute_s: float = 0.0
    sender_bits: int = 0
    sender_compute_ms: float = 0.0


@dataclass(frozen=True)
class DescriptionStats:
    """The content description the model codec used (`content`, None: none), its size, its
    bits on the wire (headers and repeats included), when its last chunk reached the receiver,
    when a report told the engine, and how long the model codec was wanted without it."""

    content: Any = None
    size_bytes: int = 0
    sent_bits: int = 0
    delivered_s: float | None = None
    acked_s: float | None = None
    wait_s: float = 0.0


@dataclass(frozen=True)
class RefreshStats:
    """The model-aided refresh in a finished run: its bits on the wire (headers included), the
    engine compute modelled for it, the refreshes the receiver decoded and those it lost."""

    bits: int = 0
    compute_s: float = 0.0
    decoded: int = 0
    lost: int = 0
