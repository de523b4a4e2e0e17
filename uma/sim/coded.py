"""What an engine-side encoder returns for one picture (`uma.sim.codecs`).

Units: sizes in pixels, data in bytes, cost in evaluations (the codec's own unit of work).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Coded"]


@dataclass(frozen=True)
class Coded:
    """One coded picture: its bytes, whether it is intra, what it cost; `failure` (a reason)
    when the codec could not code it (MBC lost the face), with `data` empty."""

    data: bytes
    keyframe: bool
    width: int
    height: int
    evaluations: int = 0
    failure: str = ""
    reinitialised: bool = False
    frames: tuple[int, ...] = ()  # frames in `data` when several; () with no data: buffered
