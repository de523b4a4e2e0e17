"""Bandwidth traces: the `Trace` type, one reader per format, uma's own CSV, technology models,
and the route builder that chains them into a commute.

Units: seconds and kbit/s throughout; per-technology delays in ms (one way).
"""

from uma.traces.labelled import read_labelled_csv
from uma.traces.labels import LABELS, normalise_technology, technology_label
from uma.traces.read import FORMATS, read_trace, sniff_format
from uma.traces.readers import (
    DEFAULT_BIN_MS,
    read_bytes_per_sec,
    read_hsdpa_log,
    read_mahimahi,
    read_nyu_mets,
    read_nyu_mets_multivariate,
    read_pensieve,
)
from uma.traces.route import RouteSegment, build_route
from uma.traces.technology import (
    TECHNOLOGIES,
    RateModel,
    Technology,
    generate,
    technology_defaults,
)
from uma.traces.trace import Trace, concatenate
from uma.traces.uma_csv import read_uma_csv, write_uma_csv

__all__ = [
    "Trace",
    "concatenate",
    "read_trace",
    "sniff_format",
    "FORMATS",
    "read_mahimahi",
    "DEFAULT_BIN_MS",
    "read_pensieve",
    "read_hsdpa_log",
    "read_labelled_csv",
    "read_bytes_per_sec",
    "read_nyu_mets",
    "read_nyu_mets_multivariate",
    "read_uma_csv",
    "write_uma_csv",
    "LABELS",
    "technology_label",
    "normalise_technology",
    "RateModel",
    "Technology",
    "TECHNOLOGIES",
    "technology_defaults",
    "generate",
    "RouteSegment",
    "build_route",
]
