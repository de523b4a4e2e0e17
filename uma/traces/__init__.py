"""Bandwidth traces: one reader per format, uma's own CSV, technology models, the route builder."""

from uma.traces.readers import FORMATS, read_trace, sniff_format, write_uma_csv
from uma.traces.route import RouteSegment, build_route
from uma.traces.technology import (
    TECHNOLOGIES,
    Technology,
    generate,
    normalise_technology,
    technology_defaults,
)
from uma.traces.trace import Trace

__all__ = [
    "Trace",
    "read_trace",
    "write_uma_csv",
    "sniff_format",
    "FORMATS",
    "RouteSegment",
    "build_route",
    "Technology",
    "TECHNOLOGIES",
    "technology_defaults",
    "normalise_technology",
    "generate",
]
