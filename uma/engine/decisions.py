"""What the engine hands the world: its decisions, the actions they carry, and its events.

Units: times in seconds, rates in kbit/s, sizes in bits.

Everything the engine wants done leaves through these values; the world carries them out and
reports the outcome back through the engine's `on_*` methods. The engine's events leave once,
at the end of a run, in `EngineOutcome`.
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.engine.points import OperatingPoint
from uma.engine.refresh import RefreshOrder

__all__ = [
    "FrameDecision",
    "EngineEvent",
    "DescriptionChunk",
    "UnitSent",
    "PaceDecision",
    "EngineOutcome",
]


@dataclass(frozen=True)
class EngineEvent:
    time_s: float
    kind: str
    detail: str


@dataclass(frozen=True)
class DescriptionChunk:
    """Send chunk `chunk` of the content description's `count`, as packet `seq` of `size_bits`."""

    seq: int
    chunk: int
    count: int
    size_bits: int


@dataclass(frozen=True)
class FrameDecision:
    """What to do with one source frame.

    `rung` is the index of the operating point `point` in the engine's ladder; `point` names
    the codec and the compute it models. `scheduled` is False when the point's frame rate
    leaves this frame out (no freeze: the rate is lower by design); `send` is False also when
    the engine skips a scheduled frame because the downlink is backlogged (the display will
    freeze). `initialise`: the index of the model codec's point to start an initialisation
    of on this frame's decoded picture (then call `on_init_done`), or None. `description`:
    the content description's packets to send now, before the frame (each already counted in
    flight). `estimate_kbps`: the bandwidth estimate the decision was taken on;
    `queued_bits`: what waited in the engine's own queue (the pacer's) then. `refresh`: a
    model-aided refresh to code of this frame's picture (`uma.engine.refresh`), or None;
    `refresh_adopted`: the frame of a refresh the receiver now renders from, that the
    encoder's mirror of it should take too (None: no change).
    """

    frame: int
    rung: int
    scheduled: bool
    send: bool
    force_idr: bool
    point: OperatingPoint
    reason: str = ""
    initialise: int | None = None
    description: tuple[DescriptionChunk, ...] = ()
    estimate_kbps: float = 0.0
    queued_bits: int = 0
    refresh: RefreshOrder | None = None
    refresh_adopted: int | None = None

    @property
    def codec(self) -> str:
        return self.point.codec


@dataclass(frozen=True)
class UnitSent:
    """The engine's answer to a coded unit handed to the downlink: the first sequence number of
    its packets, and `padding_bits` to send behind it (None: no padding is due; it may be 0 or
    less when the unit fills its share already)."""

    first_seq: int
    padding_bits: float | None = None


@dataclass(frozen=True)
class PaceDecision:
    """What the pacer lets out now: the world's packets in order, each with its sequence
    number, and when to ask again (inf: when something new is queued)."""

    sent: tuple[tuple[object, int], ...]
    next_s: float


@dataclass(frozen=True)
class EngineOutcome:
    """What the engine leaves behind when the run ends: its events in order, its counts, and
    the content description's delivery (`description_acked_s`: when a report confirmed it, None
    if never; `description_wait_s`: how long the model codec was wanted but waited for it)."""

    events: tuple[EngineEvent, ...]
    counts: dict[str, int]
    description_acked_s: float | None
    description_wait_s: float
