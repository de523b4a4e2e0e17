"""Rate policies: which rung of the H.264 ladder to send, as pure functions of the engine's state.

Units: rates in kbit/s, times in seconds. A policy takes a `PolicyView` and returns a rung index
(0 = lowest rate). Policies are looked up by name from the scenario (`engine.policy`), so a new
one is a function plus a line in `POLICIES`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

__all__ = [
    "PolicyView",
    "POLICIES",
    "throughput_policy",
    "oracle_policy",
    "fixed_policy",
    "highest_fitting",
]


@dataclass(frozen=True)
class PolicyView:
    """All a policy may look at.

    `capacity_kbps` is the true current downlink capacity, known only to the oracle (None for
    real policies); `rung_rates_kbps` ascend.
    """

    now_s: float
    rung_rates_kbps: tuple[float, ...]
    current_rung: int
    last_switch_s: float
    estimate_kbps: float
    safety: float
    up_hold_s: float
    capacity_kbps: float | None = None
    fixed_rung: int | None = None


def highest_fitting(rates_kbps: tuple[float, ...], budget_kbps: float) -> int:
    """The highest rung whose rate fits `budget_kbps`, or 0 when none does."""
    best = 0
    for index, rate in enumerate(rates_kbps):
        if rate <= budget_kbps:
            best = index
    return best


def throughput_policy(view: PolicyView) -> int:
    """Down at once to what the estimate carries; up one rung at a time after `up_hold_s`."""
    target = highest_fitting(view.rung_rates_kbps, view.safety * view.estimate_kbps)
    if target < view.current_rung:
        return target
    if target > view.current_rung and view.now_s - view.last_switch_s >= view.up_hold_s:
        return view.current_rung + 1
    return view.current_rung


def oracle_policy(view: PolicyView) -> int:
    """Knows the true capacity: the highest rung within `safety` of it, no hold (an upper bound)."""
    if view.capacity_kbps is None:
        raise ValueError("oracle policy needs the true capacity")
    return highest_fitting(view.rung_rates_kbps, view.safety * view.capacity_kbps)


def fixed_policy(view: PolicyView) -> int:
    """Always the configured rung: the non-adaptive baseline."""
    if view.fixed_rung is None:
        raise ValueError("fixed policy needs fixed_rung")
    return min(view.fixed_rung, len(view.rung_rates_kbps) - 1)


POLICIES: dict[str, Callable[[PolicyView], int]] = {
    "throughput": throughput_policy,
    "oracle": oracle_policy,
    "fixed": fixed_policy,
}
