"""The display rule, and an exact offline replay of it on a run's recorded decoded frames.

Units: seconds, except the `_ms` arrays of a replay. Pure (no SimPy).

The playout is downstream of everything else in a run: the display asks the playout its delay
and shows the newest decoded frame, and nothing it does reaches the receiver, the links or the
engine. So the frames a run decoded, in the order the receiver decoded them (`RunResult.decoded`),
with the frames the engine scheduled and the route's technologies, are all a playout setting
needs: `replay` runs the display rule on them with any receiver playout setting and gives the
display instants, shown frames and frozen flags the full run with that setting would give.
`DisplayRule` and `newest_decoded` are the rule itself; `uma.sim.processes.display_process` uses
them on the receiver's decoded pictures, so the replay cannot drift from the simulation.
"""

from __future__ import annotations

from collections.abc import Callable, MutableMapping
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from uma.config.scenario import AdaptivePlayoutConfig, ReceiverConfig
from uma.sim.playout import make_playout

__all__ = [
    "DecodedFrame",
    "DisplayRule",
    "newest_decoded",
    "PlayoutRecording",
    "Replay",
    "recording_of",
    "replay",
]


class DecodedFrame(NamedTuple):
    """A picture the receiver can show from `decode_s` on; `told`: the playout was told of it
    (a frame of the video chain; a model-aided refresh's picture is not)."""

    frame: int
    capture_s: float
    decode_s: float
    told: bool


def newest_decoded(decoded: MutableMapping[int, Any], frame: int) -> int:
    """The newest frame of `decoded` not newer than `frame` (-1: none); older ones are let go."""
    candidates = [k for k in decoded if k <= frame]
    if not candidates:
        return -1
    shown = max(candidates)
    for k in [k for k in decoded if k < shown]:
        del decoded[k]
    return shown


class DisplayRule:
    """Each display instant: its deadline (the frame's capture time plus the playout's delay,
    never before now), the frame it shows, and whether that freezes the display."""

    def __init__(self, playout, fps: float) -> None:
        self.playout = playout
        self.fps = fps
        self.last_scheduled = -1  # the last frame the engine meant to be seen

    def deadline_s(self, index: int, now_s: float, technology: str) -> float:
        """When frame `index` is displayed, asked at `now_s` (the previous display instant)."""
        return max(now_s, index / self.fps + self.playout.delay_s(now_s, technology))

    def show(
        self, index: int, decoded: MutableMapping[int, Any], scheduled: bool
    ) -> tuple[int, bool]:
        """At frame `index`'s deadline, with `decoded` the frames decoded by then: the frame
        shown (-1: none yet) and whether the display is frozen (not the last one scheduled)."""
        if scheduled:
            self.last_scheduled = index
        shown = newest_decoded(decoded, index)
        return shown, shown < 0 or shown != self.last_scheduled


@dataclass(frozen=True)
class PlayoutRecording:
    """What a run's display needs, besides the playout: the frames decoded, those scheduled,
    and the receiver's technology at any instant."""

    fps: float
    frames: int
    capture_ms: np.ndarray  # per frame: its capture instant
    scheduled: np.ndarray  # per frame: the engine meant it to be seen
    decoded: tuple[DecodedFrame, ...]  # in the order the receiver decoded them
    technology_at: Callable[[float], str]
    receiver: ReceiverConfig  # the run's own playout setting


@dataclass(frozen=True)
class Replay:
    """A replayed display: per frame, its display instant, the frame shown and frozen flag."""

    display_ms: np.ndarray
    shown_frame: np.ndarray
    frozen: np.ndarray


def recording_of(result) -> PlayoutRecording:
    """The playout recording of a finished run (`uma.sim.result.RunResult`)."""
    return PlayoutRecording(
        fps=result.fps,
        frames=result.log.frames,
        capture_ms=np.asarray(result.log["capture_ms"]).copy(),
        scheduled=np.asarray(result.log["scheduled"]).astype(bool),
        decoded=tuple(result.decoded),
        technology_at=result.capacity.technology_at,
        receiver=result.scenario.receiver,
    )


def replay(
    recording: PlayoutRecording,
    adaptive: AdaptivePlayoutConfig | None = None,
    *,
    receiver: ReceiverConfig | None = None,
) -> Replay:
    """The display of `recording` with the playout of `receiver` (default: the run's own), its
    adaptive setting replaced by `adaptive` when given."""
    receiver = receiver if receiver is not None else recording.receiver
    if adaptive is not None:
        receiver = receiver.model_copy(update={"adaptive": adaptive})
    playout = make_playout(receiver)
    rule = DisplayRule(playout, recording.fps)
    frames, decoded = recording.frames, recording.decoded
    display_ms = np.full(frames, np.nan)
    shown_frame = np.full(frames, -1, dtype=np.int64)
    frozen = np.zeros(frames, dtype=np.int64)
    shown_so_far: dict[int, None] = {}
    now_s, j = 0.0, 0
    for index in range(frames):
        now_s = rule.deadline_s(index, now_s, recording.technology_at(now_s))
        while j < len(decoded) and decoded[j].decode_s <= now_s:
            entry = decoded[j]
            shown_so_far[entry.frame] = None
            if entry.told:
                playout.on_decoded(entry.capture_s, entry.decode_s)
            j += 1
        shown, is_frozen = rule.show(index, shown_so_far, bool(recording.scheduled[index]))
        display_ms[index] = now_s * 1000.0
        shown_frame[index] = shown
        frozen[index] = int(is_frozen)
    return Replay(display_ms=display_ms, shown_frame=shown_frame, frozen=frozen)
