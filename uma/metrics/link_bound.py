"""The least capture-to-display delay a link allows any sender, frame by frame.

Units: seconds inside, milliseconds in the summary's names. Pure: the link is a piecewise-constant
capacity (`uma.sim.capacity.CapacitySchedule` or anything with its `starts_s`, `rates_bps`,
`cum_bits`, `technologies` and `bits_until_many`) and a one-way delay per technology.

The delay is counted as `uma.metrics.delay` counts it (Salsify's): a frame's delay is the time from
its capture to the first display of it or a newer frame. No frame captured at or after `c` can be
shown before a packet started at `c` or later has crossed the link, so a frame captured at `c` is
delayed at least `t_arrive(c) - c`, where `t_arrive(c)` is the earliest arrival of a packet of
`size_bits` that starts at or after `c` on an otherwise empty link (its transmission at the
capacity, then the technology's one-way delay; a later start can arrive sooner only across a
handover to a technology of less delay, which the search covers). That holds for every engine,
rate control and playout: queues, other packets, loss, the uplink, coding and the display's ticks
only add to it. Times are searched on a grid of `step_s` (1 ms, coarser for runs so long that the
grid would pass `MAX_GRID_POINTS`) and the result is lowered by two steps, so it stays a bound.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["frame_delay_bounds_s", "bound_summary", "MAX_GRID_POINTS"]

# A 4-hour run searched at 1 ms would hold 14 million points in each of several arrays.
MAX_GRID_POINTS = 2_000_000


def _latest_start_s(link, finish_s: np.ndarray, size_bits: float) -> np.ndarray:
    """The latest start from which `size_bits` have left by each finish time (-inf: none)."""
    starts, rates, cum = link.starts_s, link.rates_bps, link.cum_bits
    target = link.bits_until_many(finish_s) - size_bits
    step = np.searchsorted(cum, target, side="right") - 1
    safe = np.clip(step, 0, None)
    # cum rises strictly across step `safe` unless it is the last step with zero rate.
    rate = np.where(rates[safe] > 0, rates[safe], np.inf)
    start = starts[safe] + (target - cum[safe]) / rate
    return np.where(step >= 0, np.minimum(start, finish_s), -np.inf)


def frame_delay_bounds_s(
    link,
    delay_s_of: Callable[[str], float],
    capture_s: np.ndarray,
    *,
    size_bits: float,
    step_s: float | None = None,
) -> np.ndarray:
    """Per capture instant, the least delay any sender and playout could give that frame."""
    if size_bits <= 0 or (step_s is not None and step_s <= 0):
        raise ValueError(f"size_bits and step_s must be positive, got {size_bits}, {step_s}")
    capture_s = np.asarray(capture_s, dtype=np.float64)
    end_s = float(capture_s.max(initial=0.0))
    link_delay_s = {tech: float(delay_s_of(tech)) for tech in set(link.technologies)}
    slowest_s = max(link_delay_s.values(), default=0.0)
    # Finish times far enough past the last capture for its packet to cross any stretch that
    # ends within the schedule, then the schedule's last rate holds.
    horizon_s = max(end_s, float(link.starts_s[-1])) + 2.0 * slowest_s + 60.0
    if step_s is None:
        step_s = max(0.001, horizon_s / MAX_GRID_POINTS)
    finish_s = np.arange(0.0, horizon_s, step_s)
    latest = _latest_start_s(link, finish_s, size_bits)
    step = np.clip(np.searchsorted(link.starts_s, finish_s, side="right") - 1, 0, None)
    per_step = np.array([link_delay_s[tech] for tech in link.technologies])
    arrive_s = finish_s + per_step[step]
    order = np.argsort(arrive_s, kind="stable")
    # The latest start whose packet has arrived by each (sorted) arrival time.
    newest_start = np.maximum.accumulate(latest[order])
    first = np.searchsorted(newest_start, capture_s, side="left")
    reached = first < newest_start.size
    arrive = np.where(reached, arrive_s[order][np.clip(first, 0, newest_start.size - 1)], np.inf)
    return np.maximum(arrive - capture_s - 2.0 * step_s, 0.0)


def bound_summary(bounds_s: np.ndarray, *, over_s: tuple[float, ...] = (1.0, 1.5)) -> dict:
    """The bounds' p95 and median in ms, and the share of frames bound above each of `over_s`."""
    finite = bounds_s[np.isfinite(bounds_s)]
    if finite.size == 0:
        return {"delay_p95_ms": None, "delay_median_ms": None, "share_over_s": {}}
    return {
        "delay_p95_ms": round(float(np.percentile(finite, 95)) * 1000.0, 1),
        "delay_median_ms": round(float(np.median(finite)) * 1000.0, 1),
        "share_over_s": {f"{s:g}": round(float((finite > s).mean()), 4) for s in over_s},
    }
