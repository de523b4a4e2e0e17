"""Salsify's skip rule as a pure function: skip a frame rather than let the queue pass the budget.

Units: bits, kbit/s (= bits per ms), ms.
"""

from __future__ import annotations

__all__ = ["should_skip", "frame_budget_bits"]


def frame_budget_bits(queued_bits: float, capacity_kbps: float, budget_ms: float) -> float:
    """The largest frame that still drains within `budget_ms` behind `queued_bits` (>= 0)."""
    return max(0.0, capacity_kbps * budget_ms - queued_bits)


def should_skip(
    frame_bits: float, queued_bits: float, capacity_kbps: float, budget_ms: float
) -> bool:
    """True when sending the frame would leave its last bit queued past `budget_ms`.

    The queue ahead (`queued_bits`: the sender's pacer and the bottleneck as last reported)
    drains at the estimated capacity; a frame that would not be through within the budget is
    skipped (the next frame is coded against the last one sent), as Salsify's sender does
    when no version of the frame fits. A capacity of zero or less skips every frame.
    """
    if capacity_kbps <= 0:
        return True
    return frame_bits > frame_budget_bits(queued_bits, capacity_kbps, budget_ms)
