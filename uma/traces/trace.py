"""A bandwidth trace: downlink capacity over time, piecewise constant, with technology labels.

Units: times in seconds, rates in kbit/s. Step i holds `rates_kbps[i]` over the half-open
interval [times_s[i], times_s[i + 1]), the last step over [times_s[-1], duration_s]. A rate of
zero is an outage. Each step carries a technology label from `uma.traces.labels.LABELS`, or ""
when unknown.

A `Trace` never merges or drops steps on its own: equal neighbours stay two steps, so a trace
read from a file keeps one step per sample and the link sees exactly what the file said.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from uma.errors import TraceError
from uma.traces.labels import LABELS, technology_label

__all__ = ["Trace", "concatenate", "MAX_STEPS", "MAX_RATE_KBPS"]

# Ten million steps (80 MB an array; 11.6 days of 100 ms bins): readers and the generator refuse
# to build more, as a file or a duration asking for that is a mistake, not a commute.
MAX_STEPS = 10_000_000

# A terabit: no radio link comes near, and beyond it a packet's serialisation time rounds to
# nothing (a rate of 1e300 made the link compute negative delays).
MAX_RATE_KBPS = 1e9

_ALLOWED = frozenset(LABELS) | {""}


def _locked(values: object, name: str, source: str) -> np.ndarray:
    """A read-only float64 copy (a frozen trace must not change under the link's feet)."""
    try:
        array = np.array(values, dtype=np.float64) + 0.0  # + 0.0 turns -0.0 into 0.0
    except (TypeError, ValueError):
        raise TraceError(f"{source}: {name} must be numbers, got {values!r:.60}") from None
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class Trace:
    """Piecewise-constant downlink capacity; validated when built, immutable afterwards.

    Equality compares the content (times, rates, technologies, duration), not `source`, which
    only names the trace in messages.
    """

    times_s: np.ndarray
    rates_kbps: np.ndarray
    technologies: tuple[str, ...]
    duration_s: float
    source: str = "<trace>"

    def __post_init__(self) -> None:
        where = str(self.source)
        object.__setattr__(self, "source", where)
        times = _locked(self.times_s, "times_s", where)
        rates = _locked(self.rates_kbps, "rates_kbps", where)
        object.__setattr__(self, "times_s", times)
        object.__setattr__(self, "rates_kbps", rates)
        object.__setattr__(self, "technologies", tuple(self.technologies))
        if times.ndim != 1 or times.size == 0:
            raise TraceError(f"{where}: no samples (expected at least one step)")
        if rates.shape != times.shape or len(self.technologies) != times.size:
            raise TraceError(
                f"{where}: {times.size} start times, {rates.size} rates and "
                f"{len(self.technologies)} technologies; expected one of each per step"
            )
        if times[0] != 0.0:
            raise TraceError(
                f"{where}: expected the first step to start at 0 s, got {float(times[0])!r}"
            )
        bad = np.flatnonzero(~(np.diff(times) > 0))  # also catches NaN
        if bad.size:
            i = int(bad[0]) + 1
            raise TraceError(
                f"{where}: step {i} starts at {float(times[i])!r} s, expected a time after "
                f"{float(times[i - 1])!r} s"
            )
        bad = np.flatnonzero(~(np.isfinite(rates) & (rates >= 0)))
        if bad.size:
            i = int(bad[0])
            raise TraceError(
                f"{where}: step {i}: expected a finite rate >= 0, got {float(rates[i])!r}"
            )
        bad = np.flatnonzero(rates > MAX_RATE_KBPS)
        if bad.size:
            i = int(bad[0])
            raise TraceError(
                f"{where}: step {i}: a rate of {float(rates[i]):g} kbit/s is above the maximum "
                f"{MAX_RATE_KBPS:g} kbit/s (a terabit)"
            )
        for i, tech in enumerate(self.technologies):
            if tech not in _ALLOWED:
                raise TraceError(
                    f"{where}: step {i}: expected a technology among {', '.join(LABELS)} "
                    f"or '', got {tech!r}"
                )
        try:
            duration = float(self.duration_s)
        except (TypeError, ValueError):
            raise TraceError(
                f"{where}: expected a duration in s, got {self.duration_s!r}"
            ) from None
        if not math.isfinite(duration) or duration <= times[-1]:
            raise TraceError(
                f"{where}: expected a duration after the last step's start {float(times[-1])!r} s, "
                f"got {duration!r}"
            )
        object.__setattr__(self, "duration_s", duration)

    @classmethod
    def constant(
        cls, rate_kbps: float, duration_s: float, *, technology: str = "", source: str = "constant"
    ) -> Trace:
        """One step of `rate_kbps` lasting `duration_s`."""
        return cls(np.zeros(1), np.array([rate_kbps]), (technology,), duration_s, source)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Trace):
            return NotImplemented
        return (
            self.duration_s == other.duration_s
            and self.technologies == other.technologies
            and np.array_equal(self.times_s, other.times_s)
            and np.array_equal(self.rates_kbps, other.rates_kbps)
        )

    def __hash__(self) -> int:
        return hash((self.duration_s, self.technologies, self.times_s.size))

    def __len__(self) -> int:
        """The number of steps."""
        return int(self.times_s.size)

    @property
    def widths_s(self) -> np.ndarray:
        """How long each step lasts."""
        return np.diff(np.append(self.times_s, self.duration_s))

    @property
    def mean_rate_kbps(self) -> float:
        """Time-weighted mean rate over the whole trace."""
        return float(np.dot(self.widths_s, self.rates_kbps) / self.duration_s)

    def step_at(self, t_s: float) -> int:
        """Index of the step holding at `t_s`; `duration_s` itself belongs to the last step."""
        t = float(t_s)
        if not 0.0 <= t <= self.duration_s:  # also rejects NaN
            raise TraceError(f"{self.source}: time {t!r} s is outside 0-{self.duration_s!r} s")
        return int(np.searchsorted(self.times_s, t, side="right")) - 1

    def rate_kbps_at(self, t_s: float) -> float:
        """The rate at `t_s` (a step edge belongs to the step it starts)."""
        return float(self.rates_kbps[self.step_at(t_s)])

    def technology_at(self, t_s: float) -> str:
        """The technology label at `t_s` ("" when the trace does not say)."""
        return self.technologies[self.step_at(t_s)]

    def window(self, start_s: float, duration_s: float) -> Trace:
        """The part from `start_s` lasting `duration_s`, re-based to start at 0.

        The window must lie inside the trace (a rounding error of 1e-9 relative is forgiven at
        the end); the step cut at `start_s` becomes the window's first step.
        """
        start, length = float(start_s), float(duration_s)
        slack = 1e-9 * max(1.0, self.duration_s)
        if not (0.0 <= start < self.duration_s and 0.0 < length <= self.duration_s - start + slack):
            raise TraceError(
                f"{self.source}: expected a window inside 0-{self.duration_s!r} s, "
                f"got {start!r} s lasting {length!r} s"
            )
        first = self.step_at(start)
        later = self.times_s[first + 1 :] - start
        later = later[later < length]
        count = 1 + later.size
        return Trace(
            np.concatenate(([0.0], later)),
            self.rates_kbps[first : first + count],
            self.technologies[first : first + count],
            length,
            self.source,
        )

    def with_technology(self, label: str, *, only_unlabelled: bool = False) -> Trace:
        """Every step labelled `label` (aliases such as HSPA+ accepted), or only the steps
        labelled "" with `only_unlabelled=True`."""
        name = technology_label(label)
        if name is None:
            raise TraceError(
                f"{self.source}: expected a technology among {', '.join(LABELS)}, got {label!r}"
            )
        techs = tuple(tech if (only_unlabelled and tech) else name for tech in self.technologies)
        return Trace(self.times_s, self.rates_kbps, techs, self.duration_s, self.source)

    def scaled(self, factor: float) -> Trace:
        """Every rate multiplied by `factor` (finite, >= 0)."""
        if not (math.isfinite(factor) and factor >= 0):
            raise TraceError(f"{self.source}: expected a finite scale >= 0, got {float(factor)!r}")
        return Trace(
            self.times_s, self.rates_kbps * factor, self.technologies, self.duration_s, self.source
        )

    def concat(self, other: Trace) -> Trace:
        """This trace, then `other` starting at this one's `duration_s`; steps are kept as they are."""
        return concatenate([self, other])


def concatenate(traces: Sequence[Trace]) -> Trace:
    """The traces one after the other (in one pass, so a long loop costs linear time)."""
    if not traces:
        raise TraceError("concatenate: expected at least one trace")
    offsets = np.cumsum([0.0] + [trace.duration_s for trace in traces])
    sources: list[str] = []
    for trace in traces:
        if not sources or sources[-1] != trace.source:
            sources.append(trace.source)
    return Trace(
        np.concatenate([trace.times_s + off for trace, off in zip(traces, offsets, strict=False)]),
        np.concatenate([trace.rates_kbps for trace in traces]),
        tuple(tech for trace in traces for tech in trace.technologies),
        float(offsets[-1]),
        "+".join(sources),
    )
