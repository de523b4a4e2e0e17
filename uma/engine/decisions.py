"""What goes into the engine and what comes out: its inputs' reports, its actions, its events.

Units: times in seconds, rates in kbit/s, sizes in bits or bytes as named.

Every call into `UmaEngine` returns the actions it causes, in the order the world carries them
out: `SendPacket` (a numbered packet to offer the downlink now), `Initialise` (start the model
codec's initialisation on this frame's picture), `AdoptRefresh` / `DiscardRefresh` (the
refresh coder's mirror follows the receiver; a coded refresh is not worth sending),
`WakePacer` (something waits in the engine's pacer: ask `on_pace` now), `EngineEvent` (log an
event) and `Tally` (count something). The engine keeps its events and counts from the actions
it returns, in one place; they leave once, at the end of a run, in `EngineOutcome`.
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.engine.points import OperatingPoint
from uma.engine.records import EngineEvent, Tally

__all__ = [
    "EngineEvent",
    "Tally",
    "SendPacket",
    "Initialise",
    "AdoptRefresh",
    "DiscardRefresh",
    "WakePacer",
    "Action",
    "RefreshOrder",
    "FrameDecision",
    "OutgoingUnit",
    "RefreshCoded",
    "CodedReport",
    "PaceDecision",
    "EngineOutcome",
]


@dataclass(frozen=True)
class SendPacket:
    """Offer the downlink this packet now, numbered `seq`. `kind` is `video` (a unit of a
    point), `refresh`, `description` (chunk `index` of `count`) or `padding`; `payload` is
    the world's unit (None for a chunk or padding); `index` of `count` is its place in it."""

    kind: str
    payload: object
    index: int
    count: int
    size_bits: int
    seq: int


@dataclass(frozen=True)
class Initialise:
    """Start initialising the model codec of point `rung` on frame `frame`'s decoded picture
    (then report `on_init_done`)."""

    rung: int
    frame: int


@dataclass(frozen=True)
class AdoptRefresh:
    """The receiver renders from the refresh of `frame` now: the coder's mirror follows."""

    frame: int


@dataclass(frozen=True)
class DiscardRefresh:
    """The refresh of `frame` just coded is not worth sending: forget it."""

    frame: int


@dataclass(frozen=True)
class WakePacer:
    """Something waits in the engine's pacer: call `on_pace` now."""


@dataclass(frozen=True)
class RefreshOrder:
    """Code a refresh of frame `frame` now: H.264 at `rate_kbps` and `fps` (so about
    1000 x `rate_kbps` / `fps` bits a refresh, whatever the interval), intra when `intra`."""

    frame: int
    rate_kbps: float
    fps: float
    intra: bool


Action = EngineEvent | Tally | SendPacket | Initialise | AdoptRefresh | DiscardRefresh | WakePacer


@dataclass(frozen=True)
class FrameDecision:
    """What to do with one source frame, and the actions that go with it.

    `rung` is the index of the operating point `point` in the engine's ladder. `scheduled` is
    False when the point's frame rate leaves this frame out (no freeze: the rate is lower by
    design); `send` is False also when the engine skips a scheduled frame because the downlink
    is backlogged (the display will freeze). When sent, code it at `point`, intra when
    `keyframe` (a change of point starts a new stream; `force_idr`: a keyframe the engine
    asked for, a switch or a receiver's request), at `target_kbps` (None: the point's rate).
    `refresh`: a model-aided refresh to code of this frame's picture, or None.
    `estimate_kbps`: the estimate the decision was taken on; `queued_bits`: what waited in the
    engine's own queue then. `actions`: carry out in order before coding the frame.
    """

    frame: int
    rung: int
    scheduled: bool
    send: bool
    force_idr: bool
    point: OperatingPoint
    reason: str = ""
    initialise: int | None = None
    estimate_kbps: float = 0.0
    queued_bits: int = 0
    refresh: RefreshOrder | None = None
    keyframe: bool = False
    target_kbps: float | None = None
    actions: tuple[Action, ...] = ()

    @property
    def codec(self) -> str:
        return self.point.codec


@dataclass(frozen=True)
class OutgoingUnit:
    """A coded unit of point `rung` carrying `frames`, `size_bytes` long; `payload` is the
    world's (the engine never looks inside)."""

    payload: object
    size_bytes: int
    rung: int
    frames: tuple[int, ...]
    keyframe: bool


@dataclass(frozen=True)
class RefreshCoded:
    """The refresh of `frame` ordered, coded: `payload` (the world's unit) of `size_bytes`,
    intra or not, and how much better than what the receiver renders it is (`gain_db`, None:
    not known)."""

    frame: int
    payload: object
    size_bytes: int
    intra: bool
    gain_db: float | None


@dataclass(frozen=True)
class CodedReport:
    """What coding frame `frame` at point `rung` came to: whether an intra picture left
    (`keyframe`), the model codec's tracker re-initialised or failed (`failure`), a buffering
    encoder's unit left over from the point before (`leftover`, sent now), and the refresh
    ordered (`refresh`: None when it could not be coded)."""

    frame: int
    rung: int
    keyframe: bool
    reinitialised: bool = False
    failure: str = ""
    leftover: OutgoingUnit | None = None
    refresh: RefreshCoded | None = None


@dataclass(frozen=True)
class PaceDecision:
    """What the pacer lets out now, and when to ask again (inf: when something is queued)."""

    sent: tuple[SendPacket, ...]
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
