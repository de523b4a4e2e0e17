"""Rate and switching policies, as pure functions of what the engine knows.

Units: rates in kbit/s, times in seconds.

A rate policy takes a `PolicyView` and returns the index of an operating point of the engine's
ladder (`uma.engine.points`); rate policies choose among its rate-ladder points only (the
full-frame rungs and, when enabled, the region rungs below them; the lowest rate first), so on
a ladder of one full-frame codec the index is its rung. Rate policies are looked up by
name from the scenario (`engine.policy`), so a new one is a function plus a line in `POLICIES`.
A switching policy (`engine.switching.policy`, `SWITCHING`) says which codec family the engine
should be on: the rate ladder's (named by its full-frame codec, `engine.codec`) or the model
codec's (`SwitchSettings.ladder`, `SwitchSettings.model`); the engine then asks the rate policy
for a point of the ladder or takes the model codec's point.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from uma.codecs import full_frame_names, model_names
from uma.engine.points import OperatingPoint, rate_indices, same_stream

__all__ = [
    "PolicyView",
    "POLICIES",
    "throughput_policy",
    "oracle_policy",
    "fixed_policy",
    "highest_fitting",
    "CLIMBS",
    "SwitchView",
    "SwitchSettings",
    "switch_settings",
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
    engine allows now (the face-region rungs left out while no face is found); `climb` how
    `throughput_policy` goes up after `up_hold_s` (one of `CLIMBS`).
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
    climb: str = "step"

    def __post_init__(self) -> None:
        if self.climb not in CLIMBS:
            raise ValueError(f"PolicyView.climb: expected one of {CLIMBS}, got {self.climb!r}")

    @property
    def rate_ladder(self) -> tuple[int, ...]:
        """Indices of the rate ladder's points (full-frame and region rungs), lowest rate first."""
        return self.ladder if self.ladder is not None else rate_indices(self.points)

    @property
    def rates_kbps(self) -> tuple[float, ...]:
        return tuple(self.points[i].rate_kbps for i in self.rate_ladder)


def highest_fitting(rates_kbps: tuple[float, ...], budget_kbps: float) -> int:
    """The highest rung whose rate fits `budget_kbps`, or 0 when none does."""
    best = 0
    for index, rate in enumerate(rates_kbps):
        if rate <= budget_kbps:
            best = index
    return best


# How the throughput policy climbs after its hold (`PolicyView.climb`).
CLIMBS = ("step", "stream", "fit")

# Up to a rung of another size (a keyframe) only when the budget is this multiple of its rate.
UPSIZE_MARGIN = 1.25


def throughput_policy(view: PolicyView) -> int:
    """Down at once to what the estimate carries; up one rung at a time after `up_hold_s`, to a
    rung of another size only with `UPSIZE_MARGIN` to spare (a new size costs a keyframe; a
    rung of the same size only retargets the encoder). `view.climb` "stream": a climb within
    one stream goes at once to its highest rung the budget carries, a new size is still one
    step with the margin; "fit": at once to the highest rung the budget carries, of another size
    only with the margin (one keyframe for the whole climb).

    From a point off the rate ladder (the model codec's), straight to the highest rung that fits.
    """
    rungs = view.rate_ladder
    target = highest_fitting(view.rates_kbps, view.safety * view.estimate_kbps)
    if view.current not in rungs:
        return rungs[target]
    current = rungs.index(view.current)
    if target < current:
        return rungs[target]
    if target > current and view.now_s - view.last_switch_s >= view.up_hold_s:
        if view.climb == "fit":
            return _fitting_top(view, rungs, current, target)
        up = rungs[current + 1]
        if same_stream(view.points[up], view.points[view.current]):
            return _same_stream_top(view, rungs, current, target) if view.climb == "stream" else up
        # a new size costs a keyframe: only with room to spare (hysteresis)
        if view.safety * view.estimate_kbps >= UPSIZE_MARGIN * view.points[up].rate_kbps:
            return up
    return view.current


def _same_stream_top(view: PolicyView, rungs: tuple[int, ...], current: int, target: int) -> int:
    """The highest point of `rungs[current + 1 : target + 1]` reached from `rungs[current]`
    through points of the same stream only (a new size stops the climb)."""
    top = rungs[current]
    for index in rungs[current + 1 : target + 1]:
        if not same_stream(view.points[index], view.points[view.current]):
            break
        top = index
    return top


def _fitting_top(view: PolicyView, rungs: tuple[int, ...], current: int, target: int) -> int:
    """The highest point of `rungs[current + 1 : target + 1]` of the current stream, or of
    another size with `UPSIZE_MARGIN` to spare; `rungs[current]` when none is."""
    budget_kbps = view.safety * view.estimate_kbps
    for index in reversed(rungs[current + 1 : target + 1]):
        point = view.points[index]
        if same_stream(point, view.points[view.current]):
            return index
        if budget_kbps >= UPSIZE_MARGIN * point.rate_kbps:
            return index
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
    """Always the configured rung of the rate ladder: the non-adaptive baseline."""
    if view.fixed_rung is None:
        raise ValueError("fixed policy needs fixed_rung")
    rungs = view.rate_ladder
    return rungs[min(view.fixed_rung, len(rungs) - 1)]


POLICIES: dict[str, Callable[[PolicyView], int]] = {
    "throughput": throughput_policy,
    "oracle": oracle_policy,
    "fixed": fixed_policy,
}


@dataclass(frozen=True)
class SwitchSettings:
    """Thresholds on the safety-scaled estimate, with hysteresis and a minimum dwell.

    The families are named: `ladder` (the rate ladder, by its full-frame codec) and `model`
    (the model codec). Go to `model` when the budget falls below `to_model_below_kbps`; back to
    `ladder` when it rises above `to_ladder_above_kbps` (higher: the gap is the hysteresis);
    never leave a family less than `min_dwell_s` after arriving on it; with `calm_s` > 0, not
    back to `ladder` until `calm_s` after the last silence cut (`SwitchView.cut_s`).
    """

    to_model_below_kbps: float = 30.0
    to_ladder_above_kbps: float = 60.0
    min_dwell_s: float = 3.0
    calm_s: float = 0.0
    # Predictive only: switch this long before a technology in `low_technologies` begins.
    lookahead_s: float = 3.0
    low_technologies: tuple[str, ...] = ("GPRS", "GSM")
    ladder: str = full_frame_names()[0]
    model: str = model_names()[0]

    def __post_init__(self) -> None:
        if not 0 < self.to_model_below_kbps < self.to_ladder_above_kbps:
            raise ValueError(
                "switching: expected 0 < to_model_below_kbps < to_ladder_above_kbps, got "
                f"{self.to_model_below_kbps} and {self.to_ladder_above_kbps}"
            )


def switch_settings(config, *, ladder: str, model: str) -> SwitchSettings:
    """The `SwitchSettings` of `config` (`EngineConfig`) between the families `ladder` and
    `model`."""
    switching = config.switching
    return SwitchSettings(
        to_model_below_kbps=switching.to_mbc_below_kbps,
        to_ladder_above_kbps=switching.to_h264_above_kbps,
        min_dwell_s=switching.min_dwell_ms / 1000.0,
        calm_s=switching.calm_ms / 1000.0,
        lookahead_s=switching.lookahead_ms / 1000.0,
        low_technologies=tuple(switching.low_technologies),
        ladder=ladder,
        model=model,
    )


@dataclass(frozen=True)
class SwitchView:
    """All a switching policy may look at: the family in use and since when, the budget."""

    now_s: float
    codec: str  # the family in use: `SwitchSettings.ladder` or `SwitchSettings.model`
    since_s: float  # when the engine arrived on `codec`
    budget_kbps: float  # safety x estimate (or x true capacity for an oracle)
    # The route's coverage as a coverage map would give it: (start_s, technology), in order.
    coverage: tuple[tuple[float, str], ...] = ()
    # Oracle only: the lowest true capacity from now to `lookahead_s` ahead (x safety).
    budget_ahead_kbps: float | None = None
    # When the estimate was last cut for a silence (an off-period or a gap; -inf: never).
    cut_s: float = float("-inf")


def threshold_switch(view: SwitchView, settings: SwitchSettings) -> str:
    """The family to be on: thresholds with hysteresis and a minimum dwell on each family."""
    if view.now_s - view.since_s < settings.min_dwell_s:
        return view.codec
    if view.codec == settings.ladder and view.budget_kbps < settings.to_model_below_kbps:
        return settings.model
    if view.codec == settings.model and view.budget_kbps > settings.to_ladder_above_kbps:
        calm = settings.calm_s <= 0 or view.now_s - view.cut_s >= settings.calm_s
        return settings.ladder if calm else view.codec
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
    """Thresholds, plus the coverage map: to the model codec `lookahead_s` before a
    low-bandwidth area begins (so the initialisation is done at the boundary), and not back to
    the ladder while one is that near or under way."""
    if view.now_s - view.since_s < settings.min_dwell_s:
        return view.codec
    ahead_s = low_coverage_in_s(view.coverage, view.now_s, settings.low_technologies)
    near = ahead_s is not None and ahead_s <= settings.lookahead_s
    if near and view.codec in (settings.ladder, settings.model):
        return settings.model
    return threshold_switch(view, settings)


def oracle_switch(view: SwitchView, settings: SwitchSettings) -> str:
    """Knows the trace: on the model codec while the true capacity anywhere in the window
    ahead (the world looks `switching.oracle_lookahead_ms` into the trace) is below
    `to_model_below_kbps` (so the initialisation starts before the drop), back to the ladder
    once all of that window carries `to_ladder_above_kbps`. No dwell: looking ahead is what
    keeps it from flapping. An upper bound for real switching policies."""
    if view.budget_ahead_kbps is None:
        raise ValueError("oracle switching needs the true capacity ahead")
    if view.budget_ahead_kbps < settings.to_model_below_kbps:
        return settings.model
    if view.codec == settings.model and view.budget_ahead_kbps <= settings.to_ladder_above_kbps:
        return settings.model
    return settings.ladder


def no_switch(view: SwitchView, settings: SwitchSettings) -> str:
    """The rate ladder only."""
    return settings.ladder


SWITCHING: dict[str, Callable[[SwitchView, SwitchSettings], str]] = {
    "none": no_switch,
    "threshold": threshold_switch,
    "predictive": predictive_switch,
    "oracle": oracle_switch,
}
