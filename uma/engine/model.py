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

from collections.abc import Callable
from enum import Enum

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
    """The model codec `name`'s state, its blocking, and the counts of what happened."""

    def __init__(
        self,
        name: str,
        *,
        unavailable: str,
        retry_s: float,
        ladder_label: str,
        emit: Callable[[float, str, str], None],
        counts: dict[str, int],
    ) -> None:
        self.name = name
        self.ladder_label = ladder_label  # the rate ladder's codec, as events name it
        self.state = ModelState.OFF
        self.unavailable = unavailable
        self.retry_s = retry_s
        self.blocked_until_s = float("-inf")
        self.blocked_reason = ""
        self.blocked_logged = False
        self.emit = emit
        self.counts = counts
        for key in ("inits", "init_failures", "track_failures", f"{name}_refused"):
            counts.setdefault(key, 0)

    def fire(self, event: ModelEvent) -> None:
        key = (self.state, event)
        if key not in TRANSITIONS:
            raise RuntimeError(f"model codec: no transition from {self.state.name} on {event.name}")
        self.state = TRANSITIONS[key]

    def can(self, event: ModelEvent) -> bool:
        return (self.state, event) in TRANSITIONS

    def want(self, now_s: float, *, description_ready: bool) -> Want:
        """The policy wants the model codec at `now_s`: what to do for this frame."""
        if self.state is ModelState.ON:
            return Want.MODEL
        if self.state is ModelState.READY:
            self.fire(ModelEvent.USE)
            return Want.MODEL
        if self.state is ModelState.INITIALISING:
            return Want.LADDER
        reason = self.unavailable
        if not reason and now_s < self.blocked_until_s:
            reason = self.blocked_reason
        if not reason and not description_ready:
            return Want.WAIT
        if reason:
            if not self.blocked_logged:
                self.blocked_logged = True
                self.counts[f"{self.name}_refused"] += 1
                detail = f"{reason}; lowest {self.ladder_label} rung"
                self.emit(now_s, f"{self.name}_refused", detail)
            return Want.LOWEST
        return Want.START

    def start(self, now_s: float, budget_kbps: float) -> None:
        self.fire(ModelEvent.START)
        self.counts["inits"] += 1
        self.emit(now_s, f"{self.name}_init_start", f"budget {budget_kbps:.1f} kbps")

    def leave(self, now_s: float) -> None:
        """The policy wants the rate ladder: abandon an initialisation under way."""
        if self.state in (ModelState.INITIALISING, ModelState.READY):
            self.emit(now_s, f"{self.name}_init_abandoned", "budget recovered")
        self.fire(ModelEvent.ABANDON)
        self.blocked_logged = False

    def init_done(self, ok: bool, now_s: float, *, reason: str, evaluations: int) -> bool:
        """An initialisation finished; True when it failed (the engine falls back)."""
        if self.state is not ModelState.INITIALISING:
            return False
        if ok:
            self.fire(ModelEvent.INIT_OK)
            self.emit(now_s, f"{self.name}_init_done", f"{evaluations} evaluations; {reason}")
            return False
        self.fire(ModelEvent.INIT_FAILED)
        self.counts["init_failures"] += 1
        self._block(now_s, f"initialisation failed: {reason}", f"{self.name}_init_failed")
        return True

    def track_failed(self, reason: str, now_s: float) -> bool:
        """The tracker lost the face; True when the model codec was on (the engine falls back)."""
        if self.state is not ModelState.ON:
            return False
        self.fire(ModelEvent.TRACK_FAILED)
        self.counts["track_failures"] += 1
        self._block(now_s, f"tracking failed: {reason}", f"{self.name}_track_failed")
        return True

    def _block(self, now_s: float, reason: str, kind: str) -> None:
        self.blocked_until_s = now_s + self.retry_s
        self.blocked_reason = reason
        self.blocked_logged = True
        self.emit(now_s, kind, reason)
