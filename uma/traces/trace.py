"""A bandwidth trace: downlink capacity over time, piecewise constant, with technology labels.

Units: times in seconds, rates in kbit/s. Step i holds `rates_kbps[i]` from `times_s[i]` until
the next step starts, the last one until `duration_s`. A rate of zero is an outage.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.errors import TraceError

__all__ = ["Trace"]


@dataclass(frozen=True, eq=False)
class Trace:
    times_s: np.ndarray
    rates_kbps: np.ndarray
    technologies: tuple[str, ...]
    duration_s: float
    source: str = "<trace>"

    def __post_init__(self) -> None:
        times = np.asarray(self.times_s, dtype=np.float64)
        rates = np.asarray(self.rates_kbps, dtype=np.float64)
        object.__setattr__(self, "times_s", times)
        object.__setattr__(self, "rates_kbps", rates)
        object.__setattr__(self, "technologies", tuple(self.technologies))
        where = self.source
        if times.ndim != 1 or times.size == 0:
            raise TraceError(f"{where}: no samples")
        if rates.shape != times.shape or len(self.technologies) != times.size:
            raise TraceError(f"{where}: times, rates and technologies differ in length")
        if times[0] != 0.0:
            raise TraceError(f"{where}: first step must start at 0 s, got {times[0]}")
        if np.any(np.diff(times) <= 0):
            bad = int(np.flatnonzero(np.diff(times) <= 0)[0]) + 1
            raise TraceError(
                f"{where}: step {bad} starts at {times[bad]} s, not after {times[bad - 1]} s"
            )
        if not np.all(np.isfinite(rates)) or np.any(rates < 0):
            bad = int(np.flatnonzero(~np.isfinite(rates) | (rates < 0))[0])
            raise TraceError(f"{where}: step {bad}: expected a finite rate >= 0, got {rates[bad]}")
        if not np.isfinite(self.duration_s) or self.duration_s <= times[-1]:
            raise TraceError(f"{where}: duration {self.duration_s} s does not cover the last step")

    def _step(self, t_s: float) -> int:
        return max(0, int(np.searchsorted(self.times_s, t_s, side="right")) - 1)

    def rate_kbps_at(self, t_s: float) -> float:
        return float(self.rates_kbps[self._step(t_s)])

    def technology_at(self, t_s: float) -> str:
        return self.technologies[self._step(t_s)]

    @property
    def mean_rate_kbps(self) -> float:
        """Time-weighted mean rate over the whole trace."""
        widths = np.diff(np.append(self.times_s, self.duration_s))
        return float(np.sum(widths * self.rates_kbps) / self.duration_s)

    def window(self, start_s: float, duration_s: float) -> Trace:
        """The part from `start_s` lasting `duration_s`, re-based to 0 (must lie inside)."""
        end_s = start_s + duration_s
        if start_s < 0 or duration_s <= 0 or end_s > self.duration_s + 1e-9:
            raise TraceError(
                f"{self.source}: window {start_s}+{duration_s} s outside 0-{self.duration_s} s"
            )
        first = self._step(start_s)
        last = int(np.searchsorted(self.times_s, end_s, side="left"))
        times = np.concatenate(([start_s], self.times_s[first + 1 : last])) - start_s
        return Trace(
            times,
            self.rates_kbps[first:last],
            self.technologies[first:last],
            duration_s,
            self.source,
        )

    def with_technology(self, label: str, *, only_unlabelled: bool = False) -> Trace:
        techs = tuple(
            label if (not only_unlabelled or not tech) else tech for tech in self.technologies
        )
        return Trace(self.times_s, self.rates_kbps, techs, self.duration_s, self.source)

    def scaled(self, factor: float) -> Trace:
        return Trace(
            self.times_s, self.rates_kbps * factor, self.technologies, self.duration_s, self.source
        )

    def concat(self, other: Trace) -> Trace:
        """This trace followed by `other`."""
        return Trace(
            np.concatenate((self.times_s, other.times_s + self.duration_s)),
            np.concatenate((self.rates_kbps, other.rates_kbps)),
            self.technologies + other.technologies,
            self.duration_s + other.duration_s,
            self.source if self.source == other.source else f"{self.source}+{other.source}",
        )
