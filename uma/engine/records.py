"""The two actions every part of the engine may return: log an event, count something.

Units: times in seconds. The engine keeps both from the actions its parts return, in one place
(`UmaEngine._keep`); the parts never write a shared log or count.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["EngineEvent", "Tally"]


@dataclass(frozen=True)
class EngineEvent:
    """Log this event (`events.csv`)."""

    time_s: float
    kind: str
    detail: str


@dataclass(frozen=True)
class Tally:
    """Count `n` more of `key` (the run's engine counts; 0 declares the key)."""

    key: str
    n: int = 1
