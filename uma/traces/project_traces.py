"""The project's own traces in `traces/`, generated from the technology models with fixed seeds.

Units: seconds and kbit/s. Regenerate them (byte for byte) with

    python -m uma.traces.project_traces [DIR]      # DIR defaults to the project's traces/

Each is a route of generated segments (`uma.traces.route`) written with `write_uma_csv`; a
segment with `scale=0` is an outage of that technology (the radio stays attached, nothing
flows), like the UCC drive's 80 s of GPRS at 0 kbit/s.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

from uma.traces.route import RouteSegment, build_route
from uma.traces.trace import Trace

__all__ = ["ProjectTrace", "PROJECT_TRACES", "build_project_trace", "main"]


@dataclass(frozen=True)
class ProjectTrace:
    name: str
    seed: int
    segments: tuple[RouteSegment, ...]
    what: str


PROJECT_TRACES: tuple[ProjectTrace, ...] = (
    ProjectTrace(
        "cell-edge-fallback.csv",
        7,
        (
            RouteSegment("3G", 20),
            RouteSegment("GPRS", 25),
            RouteSegment("GSM", 20),
            RouteSegment("GPRS", 15),
        ),
        "80 s: 3G, a fall back to GPRS, GSM data, GPRS again",
    ),
    ProjectTrace(
        "gprs-outage.csv",
        11,
        (
            RouteSegment("EDGE", 20),
            RouteSegment("GPRS", 20),
            RouteSegment("GPRS", 15, scale=0.0),
            RouteSegment("GSM", 15),
            RouteSegment("EDGE", 10),
        ),
        "80 s: EDGE fades to GPRS, 15 s of GPRS at 0 kbit/s, GSM data, EDGE again",
    ),
)


def build_project_trace(spec: ProjectTrace) -> Trace:
    """The trace `spec` describes (the same every time)."""
    trace = build_route(spec.segments, rng=spec.seed)
    return Trace(trace.times_s, trace.rates_kbps, trace.technologies, trace.duration_s, spec.name)


def main(argv: list[str] | None = None) -> int:
    """Write every project trace into the folder given (default: the project's traces/)."""
    from uma.paths import traces_dir
    from uma.traces.uma_csv import write_uma_csv

    args = sys.argv[1:] if argv is None else argv
    folder = Path(args[0]) if args else traces_dir()
    for spec in PROJECT_TRACES:
        write_uma_csv(build_project_trace(spec), folder / spec.name)
        print(folder / spec.name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
