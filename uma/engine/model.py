"""The model codec's sub-machine: one Enum of states, one transition table (as h11 keeps its
connection states).

Units: times in seconds, rates in kbit/s.

A model codec must be initialised on a decoded picture before it can send. While the switching
policy wants it, the machine goes `OFF` -> `INITIALISING` (the world runs the initialisation
and reports back) -> `READY` -> `ON` (its point is used from the next frame). A failed
initialisation or a lost track sends it back `OFF`, blocked for `retry_s` with the reason
kept; without a content description (`unavailable`) it never starts. While blocked or
refused the engine stays on the lowest rung of the rate ladder and says why once
(`<codec>_refused`); when the policy wants the rate ladder again, any initialisation under way
is abandoned. Events are named after the codec (`<codec>_init_start`, `<codec>_init_done`,
`<codec>_init_failed`, `<codec>_track_failed`, `<codec>_init_abandoned`), as are the refusal
counts (`<codec>_refused`).
"""

from __future__ import annotations

from enum import Enum

from uma.engine.records import EngineEvent, Tally

__all__ = ["ModelState", "ModelEvent", "TRANSITIONS", "ModelMachine", "Want"]


class ModelState(Enum):
    OFF = "off"
    INITIALISING = "initialising"
    READY = "ready"
    ON = "on"


class ModelEvent(Enum):
    START = "start"  # the policy wants the model codec and nothing blocks it
    INIT_OK = "init_ok"
    INIT_FAILED = "init_failed"
    USE = "use"  # the first frame on the model codec's point
    TRACK_FAILED = "track_failed"
    ABANDON = "abandon"  # the policy wants the rate ladder


S, E = ModelState, ModelEvent
TRANSITIONS: dict[tuple[ModelState, ModelEvent], ModelState] = {
    (S.OFF, E.START): S.INITIALISING,
    (S.INITIALISING, E.INIT_OK): S.READY,
    (S.INITIALISING, E.INIT_FAILED): S.OFF,
    (S.READY, E.USE): S.ON,
    (S.ON, E.TRACK_FAILED): S.OFF,
    **{(state, E.ABANDON): S.OFF for state in ModelState},
}


class Want(Enum):
    """What the engine does for a frame while the policy wants the model codec."""

    LADDER = "ladder"  # ask the rate policy: an initialisation is under way
    WAIT = "wait"  # ask the rate policy: the receiver does not hold the description yet
    LOWEST = "lowest"  # the lowest rung of the rate ladder (refused or blocked)
    MODEL = "model"  # the model codec's point
    START = "start"  # ask the rate policy, and start an initialisation on this frame


class ModelMachine:
    """The model codec `name`'s state and its blocking. Its transitions return the actions
    they cause (events and counts); `want` only looks."""

    def __init__(self, name: str, *, unavailable: str, retry_s: float, ladder_label: str) -> None:
        self.name = name
        self.ladder_label = ladder_label  # the rate ladder's codec, as events name it
        self.state = ModelState.OFF
        self.unavailable = unavailable
        self.retry_s = retry_s
        self.blocked_until_s = float("-inf")
        self.blocked_reason = ""
        self.blocked_logged = False

    def declared(self) -> list[Tally]:
        """The counts a run reports even when nothing happened."""
        keys = ("inits", "init_failures", "track_failures", f"{self.name}_refused")
        return [Tally(key, 0) for key in keys]

    def fire(self, event: ModelEvent) -> None:
        key = (self.state, event)
        if key not in TRANSITIONS:
            raise RuntimeError(f"model codec: no transition from {self.state.name} on {event.name}")
        self.state = TRANSITIONS[key]

    def can(self, event: ModelEvent) -> bool:
        return (self.state, event) in TRANSITIONS

    def want(self, now_s: float, *, description_ready: bool) -> Want:
        """What to do for a frame at `now_s` while the policy wants the model codec (a query:
        `use`, `refuse` or `start` carry it out)."""
        if self.state in (ModelState.ON, ModelState.READY):
            return Want.MODEL
        if self.state is ModelState.INITIALISING:
            return Want.LADDER
        if self._refusal(now_s):
            return Want.LOWEST
        return Want.START if description_ready else Want.WAIT

    def _refusal(self, now_s: float) -> str:
        reason = self.unavailable
        if not reason and now_s < self.blocked_until_s:
            reason = self.blocked_reason
        return reason

    def use(self) -> None:
        """The first frame on the model codec's point once it is ready."""
        if self.state is ModelState.READY:
            self.fire(ModelEvent.USE)

    def refuse(self, now_s: float) -> list:
        """The model codec is wanted but refused or blocked: say why, once."""
        if self.blocked_logged:
            return []
        self.blocked_logged = True
        detail = f"{self._refusal(now_s)}; lowest {self.ladder_label} rung"
        return [Tally(f"{self.name}_refused"), EngineEvent(now_s, f"{self.name}_refused", detail)]

    def start(self, now_s: float, budget_kbps: float) -> list:
        self.fire(ModelEvent.START)
        detail = f"budget {budget_kbps:.1f} kbps"
        return [Tally("inits"), EngineEvent(now_s, f"{self.name}_init_start", detail)]

    def leave(self, now_s: float) -> list:
        """The policy wants the rate ladder: abandon an initialisation under way."""
        out = []
        if self.state in (ModelState.INITIALISING, ModelState.READY):
            out.append(EngineEvent(now_s, f"{self.name}_init_abandoned", "budget recovered"))
        self.fire(ModelEvent.ABANDON)
        self.blocked_logged = False
        return out

    def init_done(self, ok: bool, now_s: float, *, reason: str, evaluations: int) -> list:
        """An initialisation finished: its actions (none when none was under way); a failure
        blocks the model codec (`failed` tells the engine to fall back)."""
        if self.state is not ModelState.INITIALISING:
            return []
        if ok:
            self.fire(ModelEvent.INIT_OK)
            detail = f"{evaluations} evaluations; {reason}"
            return [EngineEvent(now_s, f"{self.name}_init_done", detail)]
        self.fire(ModelEvent.INIT_FAILED)
        kind = f"{self.name}_init_failed"
        return [
            Tally("init_failures"),
            self._block(now_s, f"initialisation failed: {reason}", kind),
        ]

    def track_failed(self, reason: str, now_s: float) -> list:
        """The tracker lost the face: its actions (none when the model codec was not on)."""
        if self.state is not ModelState.ON:
            return []
        self.fire(ModelEvent.TRACK_FAILED)
        kind = f"{self.name}_track_failed"
        return [Tally("track_failures"), self._block(now_s, f"tracking failed: {reason}", kind)]

    def _block(self, now_s: float, reason: str, kind: str) -> EngineEvent:
        self.blocked_until_s = now_s + self.retry_s
        self.blocked_reason = reason
        self.blocked_logged = True
        return EngineEvent(now_s, kind, reason)
