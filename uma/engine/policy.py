"""Rate and switching policies, as pure functions of what the engine knows.

Units: rates in kbit/s, times in seconds.

A rate policy takes a `PolicyView` and returns the index of an operating point of the engine's
ladder (`uma.engine.points`); rate policies choose among its rate-ladder points only (`h264`
and, when enabled, the face-region `h264-face` rungs below them; the lowest rate first), so on
an H.264-only ladder the index is the H.264 rung. Rate policies are looked up by
name from the scenario (`engine.policy`), so a new one is a function plus a line in `POLICIES`.
A switching policy (`engine.switching.policy`, `SWITCHING`) says which codec the engine should
be on; the engine then asks the rate policy for an H.264 point or takes the MBC point.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from uma.engine.points import OperatingPoint, rate_indices

__all__ = [
    "PolicyView",
    "POLICIES",
    "throughput_policy",
    "oracle_policy",
    "fixed_policy",
    "highest_fitting",
    "SwitchView",
    "SwitchSettings",
    "SWITCHING",
    "threshold_switch",
    "predictive_switch",
    "oracle_switch",
    "no_switch",
    "low_coverage_in_s",
]


@dataclass(frozen=True)
class PolicyView:
    """All a rate policy may look at.

    `capacity_kbps` is the true current downlink capacity, known only to the oracle (None for
    real policies); `points` is the engine's ladder, `current` the index of the point in use;
    `fixed_rung` counts rate-ladder points only; `ladder`, when given, is the rate ladder the
    engine allows now (the face-region rungs left out while no face is found).
    """

    now_s: float
    points: tuple[OperatingPoint, ...]
    current: int
    last_switch_s: float
    estimate_kbps: float
    safety: float
    up_hold_s: float
    capacity_kbps: float | None = None
    fixed_rung: int | None = None
    ladder: tuple[int, ...] | None = None

    @property
    def h264(self) -> tuple[int, ...]:
        """Indices of the rate ladder's points (H.264, face-region H.264), lowest rate first."""
        return self.ladder if self.ladder is not None else rate_indices(self.points)

    @property
    def h264_rates_kbps(self) -> tuple[float, ...]:
        return tuple(self.points[i].rate_kbps for i in self.h264)


def highest_fitting(rates_kbps: tuple[float, ...], budget_kbps: float) -> int:
    """The highest rung whose rate fits `budget_kbps`, or 0 when none does."""
    best = 0
    for index, rate in enumerate(rates_kbps):
        if rate <= budget_kbps:
            best = index
    return best


def throughput_policy(view: PolicyView) -> int:
    """Down at once to what the estimate carries; up one rung at a time after `up_hold_s`.

    From a point that is not H.264 (the MBC one), straight to the highest rung that fits.
    """
    h264 = view.h264
    target = highest_fitting(view.h264_rates_kbps, view.safety * view.estimate_kbps)
    if view.current not in h264:
        return h264[target]
    current = h264.index(view.current)
    if target < current:
        return h264[target]
    if target > current and view.now_s - view.last_switch_s >= view.up_hold_s:
        return h264[current + 1]
    return view.current


def oracle_policy(view: PolicyView) -> int:
    """Knows the true capacity: the throughput policy with a perfect estimate (an upper bound).

    Down at once to the highest rung within `safety` of the capacity, up one rung after
    `up_hold_s`: following every step of a fluctuating trace would cost an IDR each time.
    """
    if view.capacity_kbps is None:
        raise ValueError("oracle policy needs the true capacity")
    return throughput_policy(replace(view, estimate_kbps=view.capacity_kbps))


def fixed_policy(view: PolicyView) -> int:
    """Always the configured H.264 rung: the non-adaptive baseline."""
    if view.fixed_rung is None:
        raise ValueError("fixed policy needs fixed_rung")
    h264 = view.h264
    return h264[min(view.fixed_rung, len(h264) - 1)]


POLICIES: dict[str, Callable[[PolicyView], int]] = {
    "throughput": throughput_policy,
    "oracle": oracle_policy,
    "fixed": fixed_policy,
}


@dataclass(frozen=True)
class SwitchSettings:
    """Thresholds on the safety-scaled estimate, with hysteresis and a minimum dwell.

    Go to MBC when the budget falls below `to_mbc_below_kbps`; back to H.264 when it rises
    above `to_h264_above_kbps` (higher: the gap is the hysteresis); never leave a codec less
    than `min_dwell_s` after arriving on it.
    """

    to_mbc_below_kbps: float = 30.0
    to_h264_above_kbps: float = 60.0
    min_dwell_s: float = 3.0
    # Predictive only: switch this long before a technology in `low_technologies` begins.
    lookahead_s: float = 3.0
    low_technologies: tuple[str, ...] = ("GPRS", "GSM")

    def __post_init__(self) -> None:
        if not 0 < self.to_mbc_below_kbps < self.to_h264_above_kbps:
            raise ValueError(
                "switching: expected 0 < to_mbc_below_kbps < to_h264_above_kbps, got "
                f"{self.to_mbc_below_kbps} and {self.to_h264_above_kbps}"
            )


@dataclass(frozen=True)
class SwitchView:
    """All a switching policy may look at: the codec in use and since when, the budget."""

    now_s: float
    codec: str
    since_s: float  # when the engine arrived on `codec`
    budget_kbps: float  # safety x estimate (or x true capacity for an oracle)
    # The route's coverage as a coverage map would give it: (start_s, technology), in order.
    coverage: tuple[tuple[float, str], ...] = ()
    # Oracle only: the lowest true capacity from now to `lookahead_s` ahead (x safety).
    budget_ahead_kbps: float | None = None


def threshold_switch(view: SwitchView, settings: SwitchSettings) -> str:
    """The codec to be on: thresholds with hysteresis and a minimum dwell on each codec."""
    if view.now_s - view.since_s < settings.min_dwell_s:
        return view.codec
    if view.codec == "h264" and view.budget_kbps < settings.to_mbc_below_kbps:
        return "mbc"
    if view.codec == "mbc" and view.budget_kbps > settings.to_h264_above_kbps:
        return "h264"
    return view.codec


def low_coverage_in_s(
    coverage: tuple[tuple[float, str], ...], now_s: float, low: tuple[str, ...]
) -> float | None:
    """Seconds until the coverage map enters a low technology (0 inside one), None if never."""
    for index, (start_s, technology) in enumerate(coverage):
        end_s = coverage[index + 1][0] if index + 1 < len(coverage) else float("inf")
        if end_s <= now_s or technology not in low:
            continue
        return max(0.0, start_s - now_s)
    return None


def predictive_switch(view: SwitchView, settings: SwitchSettings) -> str:
    """Thresholds, plus the coverage map: to MBC `lookahead_s` before a low-bandwidth area
    begins (so the initialisation is done at the boundary), and not back to H.264 while one
    is that near or under way."""
    if view.now_s - view.since_s < settings.min_dwell_s:
        return view.codec
    ahead_s = low_coverage_in_s(view.coverage, view.now_s, settings.low_technologies)
    near = ahead_s is not None and ahead_s <= settings.lookahead_s
    if view.codec == "h264" and near:
        return "mbc"
    if view.codec == "mbc" and near:
        return "mbc"
    return threshold_switch(view, settings)


def oracle_switch(view: SwitchView, settings: SwitchSettings) -> str:
    """Knows the trace: on MBC while the true capacity anywhere in the window ahead (the world
    looks `switching.oracle_lookahead_ms` into the trace) is below `to_mbc_below_kbps` (so the initialisation starts before the drop), back to H.264
    once all of that window carries `to_h264_above_kbps`. No dwell: looking ahead is what
    keeps it from flapping. An upper bound for real switching policies."""
    if view.budget_ahead_kbps is None:
        raise ValueError("oracle switching needs the true capacity ahead")
    if view.budget_ahead_kbps < settings.to_mbc_below_kbps:
        return "mbc"
    if view.codec == "mbc" and view.budget_ahead_kbps <= settings.to_h264_above_kbps:
        return "mbc"
    return "h264"


def no_switch(view: SwitchView, settings: SwitchSettings) -> str:
    """H.264 only."""
    return "h264"


SWITCHING: dict[str, Callable[[SwitchView, SwitchSettings], str]] = {
    "none": no_switch,
    "threshold": threshold_switch,
    "predictive": predictive_switch,
    "oracle": oracle_switch,
}
