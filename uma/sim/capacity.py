"""The downlink's capacity over time: piecewise constant, with handover gaps; pure (no SimPy).

Units: times in seconds, rates in bit/s inside (kbit/s at the edges, as the traces give them),
sizes in bits. After the trace's last step the last rate holds (a run may drain its queue).

`finish_time_s` answers the link's one question exactly: a packet whose first bit starts at t0
ends when the capacity integral from t0 reaches its size. Stretches of zero capacity (outages,
handover gaps) simply hold the packet; if the capacity never returns, the answer is infinity.
"""

from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
from collections.abc import Sequence

import numpy as np

__all__ = ["CapacitySchedule"]


class CapacitySchedule:
    """Piecewise-constant capacity: `rates_bps[i]` from `starts_s[i]` until the next start."""

    def __init__(
        self,
        starts_s: Sequence[float],
        rates_bps: Sequence[float],
        technologies: Sequence[str] | None = None,
    ) -> None:
        starts = np.asarray(starts_s, dtype=np.float64)
        rates = np.asarray(rates_bps, dtype=np.float64)
        if starts.ndim != 1 or starts.shape != rates.shape or starts.size == 0:
            raise ValueError("starts_s and rates_bps must be equal-length, non-empty 1-D sequences")
        if starts[0] != 0.0 or np.any(np.diff(starts) <= 0):
            raise ValueError("starts_s must begin at 0 and increase strictly")
        if not np.all(np.isfinite(rates)) or np.any(rates < 0):
            raise ValueError("rates_bps must be finite and non-negative")
        self.starts_s = starts
        self.rates_bps = rates
        self.technologies = tuple(technologies) if technologies is not None else ("",) * starts.size
        if len(self.technologies) != starts.size:
            raise ValueError("one technology label per step")
        # cum_bits[i]: bits the link can carry from 0 to starts_s[i].
        self.cum_bits = np.concatenate(([0.0], np.cumsum(np.diff(starts) * rates[:-1])))
        # The same numbers as Python floats: a packet's few lookups cost less on lists.
        self._starts, self._rates = starts.tolist(), rates.tolist()
        self._cum = self.cum_bits.tolist()

    @classmethod
    def from_trace(cls, trace, *, handover_gap_s: float = 0.0) -> CapacitySchedule:
        """From a `uma.traces.Trace`, with zero capacity for `handover_gap_s` at each change of
        technology (both sides labelled), as a mobile's data path pauses in a vertical handover."""
        starts = np.asarray(trace.times_s, dtype=np.float64)
        rates_bps = np.asarray(trace.rates_kbps, dtype=np.float64) * 1000.0
        techs = list(trace.technologies)
        if handover_gap_s <= 0:
            return cls(starts, rates_bps, techs)
        gaps = [
            (starts[i], starts[i] + handover_gap_s)
            for i in range(1, len(techs))
            if techs[i] and techs[i - 1] and techs[i] != techs[i - 1]
        ]
        if not gaps:
            return cls(starts, rates_bps, techs)
        points = np.unique(np.concatenate([starts] + [np.array(g) for g in gaps]))
        index = np.searchsorted(starts, points, side="right") - 1
        new_rates = rates_bps[index].copy()
        for begin, end in gaps:
            new_rates[(points >= begin) & (points < end)] = 0.0
        new_techs = [techs[i] for i in index]
        return cls(points, new_rates, new_techs)

    def _step(self, t_s: float) -> int:
        return max(0, bisect_right(self._starts, t_s) - 1)

    def rate_kbps_at(self, t_s: float) -> float:
        return self._rates[self._step(t_s)] / 1000.0

    def min_rate_kbps(self, start_s: float, end_s: float) -> float:
        """The lowest capacity anywhere in [start_s, end_s] (the oracle's look ahead)."""
        first, last = self._step(start_s), self._step(max(start_s, end_s))
        return float(self.rates_bps[first : last + 1].min()) / 1000.0

    def technology_at(self, t_s: float) -> str:
        return self.technologies[self._step(t_s)]

    def bits_until(self, t_s: float) -> float:
        """Capacity integral from 0 to `t_s`, in bits."""
        k = self._step(t_s)
        return self._cum[k] + (t_s - self._starts[k]) * self._rates[k]

    def bits_until_many(self, times_s: np.ndarray) -> np.ndarray:
        """`bits_until` of every time in `times_s` at once (a float array)."""
        step = np.clip(np.searchsorted(self.starts_s, times_s, side="right") - 1, 0, None)
        return self.cum_bits[step] + (times_s - self.starts_s[step]) * self.rates_bps[step]

    def finish_time_s(self, start_s: float, size_bits: float) -> float:
        """When a packet of `size_bits` whose transmission starts at `start_s` has fully left."""
        if size_bits <= 0:
            return start_s
        target = self.bits_until(start_s) + size_bits
        if target > self._cum[-1]:
            rate = self._rates[-1]
            if rate <= 0:
                return math.inf
            return self._starts[-1] + (target - self._cum[-1]) / rate
        j = bisect_left(self._cum, target) - 1
        # cum_bits rises strictly across step j, so its rate is positive.
        return self._starts[j] + (target - self._cum[j]) / self._rates[j]
