"""Chain technology segments into one commute: each from a trace file or a generated model.

Units: seconds and kbit/s. A trace shorter than its segment (after `offset_s`) repeats from its
start; the segment's technology labels the steps the file leaves unlabelled (and all of them
with `relabel=True`), so handovers inside a labelled file (NetworkMode) are kept.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uma.errors import TraceError
from uma.traces.readers import read_trace
from uma.traces.technology import generate, normalise_technology
from uma.traces.trace import Trace

__all__ = ["RouteSegment", "build_route"]


@dataclass(frozen=True)
class RouteSegment:
    technology: str
    duration_s: float
    trace: str | None = None
    format: str = "auto"
    offset_s: float = 0.0
    scale: float = 1.0
    relabel: bool = False


def _segment_trace(index: int, seg: RouteSegment, rng, base_dir: Path | None) -> Trace:
    if seg.duration_s <= 0:
        raise TraceError(
            f"route segment {index}: expected a positive duration_s, got {seg.duration_s}"
        )
    if seg.trace is None:
        try:
            return generate(seg.technology, seg.duration_s, rng=rng).scaled(seg.scale)
        except TraceError as err:
            raise TraceError(f"route segment {index}: {err}") from None
    path = Path(seg.trace)
    if base_dir is not None and not path.is_absolute():
        path = base_dir / path
    full = read_trace(path, format=seg.format)
    if seg.offset_s >= full.duration_s:
        raise TraceError(
            f"route segment {index}: offset_s {seg.offset_s} s is past the end of {path.name} "
            f"({full.duration_s:g} s)"
        )
    pieces = []
    remaining = seg.duration_s
    start = seg.offset_s
    while remaining > 1e-9:
        take = min(remaining, full.duration_s - start)
        pieces.append(full.window(start, take))
        remaining -= take
        start = 0.0
    out = pieces[0]
    for piece in pieces[1:]:
        out = out.concat(piece)
    label = normalise_technology(seg.technology)
    return out.with_technology(label, only_unlabelled=not seg.relabel).scaled(seg.scale)


def build_route(
    segments: Sequence[RouteSegment], *, rng=None, base_dir: str | Path | None = None
) -> Trace:
    """One trace for the whole route; generated segments draw from `rng` in order."""
    if not segments:
        raise TraceError("route: expected at least one segment")
    rng = np.random.default_rng(rng)
    base = Path(base_dir) if base_dir is not None else None
    route = _segment_trace(0, segments[0], rng, base)
    for index, seg in enumerate(segments[1:], 1):
        route = route.concat(_segment_trace(index, seg, rng, base))
    return route
