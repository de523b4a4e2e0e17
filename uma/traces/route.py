"""Chain technology segments into one commute, each from a trace file or from a rate model.

Units: seconds and kbit/s. For a segment read from a file:
- the file is read from `offset_s` on; a trace shorter than the segment (after the offset)
  starts over from its beginning (not from the offset) as often as needed, each repeat being
  whole steps of the file, so a 100 s ride can fill a 250 s segment;
- `scale` multiplies its rates (e.g. 0.5 to put a fast drive on a loaded cell);
- labels: a file without any technology label takes the segment's `technology` on every step;
  a labelled file (a `NetworkMode` log) keeps its own labels and handovers, unless the segment
  asks `relabel=True`. Steps a labelled file leaves unknown ("") stay unknown.
A segment without `trace` is generated from its technology's rate model, drawing from the
route's `rng` in segment order, so a route is reproducible from one seed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uma.errors import TraceError
from uma.traces.labels import LABELS, technology_label
from uma.traces.read import FORMATS, read_trace
from uma.traces.technology import generate
from uma.traces.trace import Trace, concatenate

__all__ = ["RouteSegment", "build_route"]


@dataclass(frozen=True)
class RouteSegment:
    """One stretch of the route: a technology for `duration_s`, from `trace` or generated.

    `technology` may be "" only for a trace segment, whose file then says the technology.
    `format`, `offset_s`, `scale` and `relabel` apply to trace segments (`scale` to generated
    ones too).
    """

    technology: str
    duration_s: float
    trace: str | Path | None = None
    format: str = "auto"
    offset_s: float = 0.0
    scale: float = 1.0
    relabel: bool = False

    def __post_init__(self) -> None:
        label = technology_label(self.technology)
        if label is None or (not label and self.trace is None):
            allowed = ", ".join(LABELS) + (" or '' (the file says)" if self.trace else "")
            raise TraceError(
                f"route segment: expected technology among {allowed}, got {self.technology!r}"
            )
        for name, low, strict in (
            ("duration_s", 0.0, True),
            ("offset_s", 0.0, False),
            ("scale", 0.0, False),
        ):
            value = getattr(self, name)
            ok = isinstance(value, int | float) and math.isfinite(value)
            if not ok or value < low or (strict and value == low):
                sign = ">" if strict else ">="
                raise TraceError(f"route segment: expected {name} {sign} {low:g}, got {value!r}")
        if self.format != "auto" and self.format not in FORMATS:
            raise TraceError(
                f"route segment: expected format auto or one of {', '.join(FORMATS)}, "
                f"got {self.format!r}"
            )
        if self.trace is None and (self.offset_s or self.relabel or self.format != "auto"):
            raise TraceError(
                "route segment: offset_s, format and relabel apply to a trace file; "
                f"this {self.technology} segment has none"
            )
        object.__setattr__(self, "technology", label)


def _looped(full: Trace, offset_s: float, duration_s: float) -> Trace:
    """`duration_s` of `full` from `offset_s`, starting over at 0 when it runs out."""
    pieces = []
    start, remaining = offset_s, duration_s
    slack = 1e-9 * max(1.0, duration_s)
    while remaining > slack:
        take = min(remaining, full.duration_s - start)
        pieces.append(full.window(start, take))
        remaining -= take
        start = 0.0
    looped = concatenate(pieces)
    # Float sums of the pieces may miss duration_s by an ulp or so: end exactly on it.
    return Trace(looped.times_s, looped.rates_kbps, looped.technologies, duration_s, looped.source)


def _segment(index: int, seg: RouteSegment, rng: np.random.Generator, base: Path | None) -> Trace:
    if seg.trace is None:
        return generate(seg.technology, seg.duration_s, rng=rng).scaled(seg.scale)
    path = Path(seg.trace)
    if base is not None and not path.is_absolute():
        path = base / path
    full = read_trace(path, format=seg.format)
    if seg.offset_s >= full.duration_s:
        raise TraceError(
            f"offset_s {seg.offset_s:g} s is past the end of {path.name} "
            f"({full.duration_s:g} s long)"
        )
    part = _looped(full, seg.offset_s, seg.duration_s).scaled(seg.scale)
    if seg.technology and (seg.relabel or not any(part.technologies)):
        part = part.with_technology(seg.technology)
    return part


def build_route(
    segments: Sequence[RouteSegment],
    *,
    rng: np.random.Generator | int | None = None,
    base_dir: str | Path | None = None,
) -> Trace:
    """One trace for the whole route, the segments one after the other.

    Relative trace paths are resolved against `base_dir` (the scenario's folder; the working
    directory when None). `rng` feeds the generated segments, in order. Errors name the
    segment: `route segment 2 (trace foo.csv): line 12 of ...`.
    """
    if not segments:
        raise TraceError("route: expected at least one segment")
    rng = np.random.default_rng(rng)
    base = Path(base_dir) if base_dir is not None else None
    parts = []
    for index, seg in enumerate(segments):
        if not isinstance(seg, RouteSegment):
            raise TraceError(f"route segment {index}: expected a RouteSegment, got {seg!r:.60}")
        try:
            parts.append(_segment(index, seg, rng, base))
        except TraceError as err:
            what = f"trace {seg.trace}" if seg.trace is not None else f"generated {seg.technology}"
            raise TraceError(f"route segment {index} ({what}): {err}") from None
    return concatenate(parts)
