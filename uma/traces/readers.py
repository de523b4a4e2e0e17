"""Readers for the measured-trace formats that carry no technology labels.

Units: every reader returns a `Trace` in seconds and kbit/s, re-based to start at 0. Errors are
`TraceError`s naming the file and the 1-based line (see `uma.traces.parsing`).

When a sample is a count over the interval that ends at its time stamp (the raw HSDPA log:
"bytes since the last data point"; Pensieve's cooked copies of it; `sec,bytes_per_sec`, whose
first row is `1`), its rate is placed on that interval, so the same ride read from the raw log
and from its cooked copy lines up. NYU-METS samples are iPerf's per-second reports, in order.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence

import numpy as np

from uma.errors import TraceError
from uma.traces.parsing import TraceFile, TraceText
from uma.traces.trace import MAX_STEPS, Trace

__all__ = [
    "read_mahimahi",
    "read_plain_mahimahi",
    "read_pensieve",
    "read_hsdpa_log",
    "read_bytes_per_sec",
    "read_nyu_mets",
    "read_nyu_mets_multivariate",
    "MAHIMAHI_PACKET_BITS",
    "DEFAULT_BIN_MS",
]

MAHIMAHI_PACKET_BITS = 1500 * 8

# 100 ms bins: a packet delivered in a bin is placed, at worst, one bin away from its real
# opportunity. Measured on the shared Mahimahi traces (TMobile-UMTS, Verizon-EVDO/LTE), the
# delivery-time error is at most 91 ms with 100 ms bins (95th percentile 15-41 ms, under one
# 25 fps frame), against 450 ms (p95 52-136 ms) with 500 ms bins: too coarse for the 95th
# percentile delays that Salsify reports on these traces. Finer bins cost little more but make
# each step's rate meaningless (20 ms bins: a rate is 0 or a multiple of 600 kbit/s).
DEFAULT_BIN_MS = 100.0

Source = str | os.PathLike | TraceFile | TraceText


def _text(source: Source) -> TraceText:
    return source if isinstance(source, TraceText) else TraceText(source)


def _intervals_ending_at(
    text: TraceText,
    stamps_s: Sequence[float],
    rates_kbps: Sequence[float],
    numbers: Sequence[int],
    first_width_s: float,
) -> Trace:
    """Sample i describes the interval (stamps[i-1], stamps[i]]; the first one lasts `first_width_s`."""
    text.check_increasing(stamps_s, numbers, "s")
    text.check_seconds_apart(stamps_s, numbers)
    stamps = np.asarray(stamps_s, dtype=np.float64)
    origin = stamps[0] - first_width_s
    starts = np.concatenate(([0.0], stamps[:-1] - origin))
    return Trace(
        starts, rates_kbps, ("",) * len(starts), float(stamps[-1] - origin), text.path.name
    )


def read_mahimahi(source: Source, *, bin_ms: float = DEFAULT_BIN_MS) -> Trace:
    """Mahimahi: each line is the ms at which one 1500-byte packet may leave; lines repeat a ms
    when several packets may. Opportunities are counted in `bin_ms` bins (see DEFAULT_BIN_MS).

    The trace lasts until its last time stamp T, the period at which mm-link repeats the file:
    an opportunity at exactly T is the first of the next period, so it counts in the first bin,
    and the last bin is cut at T (its rate is its count over its true width). So the trace's
    mean rate is exactly lines x 12,000 bit / T.
    """
    _check_bin_ms(bin_ms)
    if not isinstance(source, TraceText):
        file = source if isinstance(source, TraceFile) else TraceFile(source)
        trace = read_plain_mahimahi(file, bin_ms=bin_ms)
        if trace is not None:
            return trace
        source = TraceText(file)
    text = source
    ms = None
    if all(line.isascii() and line.isdigit() for _, line in text.lines):
        try:
            ms = np.array([int(line) for _, line in text.lines], dtype=np.float64)
        except (ValueError, OverflowError):  # past int()'s 4,300 digits, or float64's range
            ms = None  # the reader below names the line (a ValueError traceback before)
    if ms is None:
        ms = np.array(
            [text.number(n, line, "delivery time in ms", integer=True) for n, line in text.lines]
        )
    drops = np.flatnonzero(np.diff(ms) < 0)
    if drops.size:
        i = int(drops[0]) + 1
        raise text.error(
            text.lines[i][0],
            f"expected a delivery time not before {ms[i - 1]:.0f} ms, got {ms[i]:.0f} ms",
        )
    period_ms = float(ms[-1])
    if period_ms <= 0:
        raise text.error(
            text.lines[-1][0], "expected the last delivery time (the period) > 0 ms, got 0"
        )
    bins = math.ceil(period_ms / bin_ms)
    if bins > MAX_STEPS:
        raise text.error(
            text.lines[-1][0],
            f"expected a period of at most {MAX_STEPS:,} bins of {bin_ms:g} ms, got "
            f"{period_ms:.0f} ms ({bins:,} bins; give a larger bin_ms)",
        )
    return _binned(ms, period_ms, bin_ms, bins, text.path.name)


def read_plain_mahimahi(file: TraceFile, *, bin_ms: float = DEFAULT_BIN_MS) -> Trace | None:
    """`read_mahimahi` of a plain file (digits, one stamp a line, in order), parsed in one pass
    in memory a few times the file's size; None for any other, which the line-by-line reader
    reads or refuses naming the line (a sign, a `#`, a header, a stamp that goes back, ...)."""
    stamps = file.whole_numbers()
    if stamps is None:
        return None
    _check_bin_ms(bin_ms)
    if np.any(stamps[1:] < stamps[:-1]):
        return None
    period_ms = float(stamps[-1])
    bins = math.ceil(period_ms / bin_ms)
    if period_ms <= 0 or bins > MAX_STEPS:
        return None
    return _binned(stamps, period_ms, bin_ms, bins, file.path.name)


def _check_bin_ms(bin_ms: float) -> None:
    if not (math.isfinite(bin_ms) and bin_ms > 0):
        raise TraceError(f"mahimahi bin_ms: expected a duration > 0 ms, got {bin_ms!r}")


# Stamps binned at a time: each chunk's temporaries are 8 MB an array, whatever the file.
_CHUNK = 2**20


def _binned(ms: np.ndarray, period_ms: float, bin_ms: float, bins: int, name: str) -> Trace:
    """The trace of the delivery times `ms` (in order, exact as float64) in `bins` bins."""
    counts = np.zeros(bins, dtype=np.int64)
    for start in range(0, ms.size, _CHUNK):
        part = ms[start : start + _CHUNK].astype(np.float64)
        index = np.minimum((np.mod(part, period_ms) // bin_ms).astype(np.int64), bins - 1)
        counted = np.bincount(index)
        counts[: counted.size] += counted
    starts_ms = np.arange(bins) * bin_ms
    widths_ms = np.minimum(bin_ms, period_ms - starts_ms)
    rates = counts * MAHIMAHI_PACKET_BITS / widths_ms  # bits per ms = kbit/s
    return Trace(starts_ms / 1000.0, rates, ("",) * bins, period_ms / 1000.0, name)


def read_pensieve(source: Source) -> Trace:
    """Pensieve-cooked `time_s<TAB>Mbit/s` (any blanks separate). Each rate covers the interval
    that ends at its time, as in the raw log it was cooked from and in Pensieve's simulator; the
    first interval is taken as long as the second (1 s for a one-line file).

    The cooked Norway traces dropped the raw log's low-rate samples and closed the gaps, so their
    times run shorter than the ride; read the raw log (`hsdpa-log`) to keep the outages.
    """
    text = _text(source)
    stamps, rates, numbers = [], [], []
    for n, line in text.lines:
        separator = "," if "," in line else None  # `time_s,Mbit/s` under a header saying so
        time_field, rate_field = text.fields(
            n, line, separator=separator, layout="time_s<TAB>Mbit/s"
        )
        stamps.append(text.number(n, time_field, "time in s"))
        rates.append(1000.0 * text.number(n, rate_field, "rate in Mbit/s"))
        numbers.append(n)
    text.check_increasing(stamps, numbers, "s")
    first = stamps[1] - stamps[0] if len(stamps) > 1 else 1.0
    return _intervals_ending_at(text, stamps, rates, numbers, first)


def read_hsdpa_log(source: Source) -> Trace:
    """Riiser et al.'s raw HSDPA log: `unix_s ms_since_start lat lon bytes interval_ms`, where
    `bytes` arrived in the `interval_ms` before `ms_since_start`.

    A log that starts over (the ms counter goes back and the line repeats the first data line,
    as in the shared copy, which holds the 457-line log four times) ends there: the rest is
    ignored. A counter that goes back any other way is a TraceError.
    """
    text = _text(source)
    layout = "unix_s ms_since_start lat lon bytes interval_ms"
    first_fields: list[str] | None = None
    stamps, rates, numbers = [], [], []
    first_width_s = 1.0
    for n, line in text.lines:
        fields = text.fields(n, line, separator=None, layout=layout)
        if first_fields is None:
            first_fields = fields
        elif fields == first_fields:
            break  # the log starts over
        text.number(n, fields[0], "unix time in s")
        ms = text.number(n, fields[1], "ms since start")
        text.number(n, fields[2], "latitude", minimum=-90.0)
        text.number(n, fields[3], "longitude", minimum=-180.0)
        size_bytes = text.number(n, fields[4], "byte count")
        interval_ms = text.number(n, fields[5], "interval in ms", positive=True)
        if stamps and not ms / 1000.0 > stamps[-1]:
            raise text.error(
                n,
                f"expected ms_since_start after {stamps[-1] * 1000.0:g} (the counter went back "
                f"without the log starting over at line {text.lines[0][0]}), got {fields[1]}",
            )
        if not stamps:
            first_width_s = interval_ms / 1000.0
        stamps.append(ms / 1000.0)
        rates.append(size_bytes * 8.0 / interval_ms)  # bits per ms = kbit/s
        numbers.append(n)
    return _intervals_ending_at(text, stamps, rates, numbers, first_width_s)


def read_bytes_per_sec(source: Source) -> Trace:
    """`sec,bytes_per_sec` (MP-traces): row `sec` counts the bytes of the second ending at
    `sec`, so rows 1, 2, ... become steps starting at 0, 1, ... A gap between rows holds the
    later row's rate over the whole gap."""
    text = _text(source)
    stamps, rates, numbers = [], [], []
    for n, line in text.lines:
        separator = "," if "," in line else None  # `sec<TAB>bytes_per_sec` under a header
        sec, per_sec = text.fields(n, line, separator=separator, layout="sec,bytes_per_sec")
        stamps.append(text.number(n, sec, "time in s"))
        rates.append(text.number(n, per_sec, "bytes per second") * 8.0 / 1000.0)
        numbers.append(n)
    return _intervals_ending_at(text, stamps, rates, numbers, 1.0)


def _per_second(text: TraceText, rates_kbps: Sequence[float]) -> Trace:
    """One unlabelled step a second: row k of `text` covers [k, k + 1) s."""
    steps = len(rates_kbps)
    return Trace(
        np.arange(steps, dtype=np.float64), rates_kbps, ("",) * steps, float(steps), text.path.name
    )


NYU_UNITS_KBPS = {"gbits/sec": 1e6, "mbits/sec": 1e3, "kbits/sec": 1.0, "bits/sec": 1e-3}


def read_nyu_mets(source: Source) -> Trace:
    """NYU-METS `value,unit`: one iPerf report a second (unit Gbits/sec, Mbits/sec, Kbits/sec or
    bits/sec, any case); row k covers [k, k + 1) s."""
    text = _text(source)
    rates = []
    for n, line in text.lines:
        value, unit = text.fields(n, line, separator=",", layout="value,unit")
        scale = NYU_UNITS_KBPS.get(unit.lower())
        if scale is None:
            raise text.error(
                n, f"expected a unit among Gbits/sec, Mbits/sec, Kbits/sec, bits/sec, got {unit!r}"
            )
        rates.append(text.number(n, value, "rate") * scale)
    return _per_second(text, rates)


# NYU-METS's multivariate files (BB62.txt.gz, TT7.txt.gz): eight numbers a row, one row a second.
# Its README lists the columns as "throughput, LTE-neighbors, RSSI, RSRQ, Echng, TA, Speed,
# Band"; the data hold the flag third (0 or 1 in column 3 of every BB62 row, 471 of 22,005 set;
# column 5 is never 0 or 1): Mbit/s, neighbours, eNodeB changed, RSRP, RSRQ, TA, speed, band MHz.
def read_nyu_mets_multivariate(source: Source) -> Trace:
    """NYU-METS multivariate rows (`Mbit/s,neighbours,eNodeB_changed,RSRP,RSRQ,TA,speed,band`):
    row k covers [k, k + 1) s at its first column's rate. Only the rate is read: every row is
    LTE (an eNodeB change is a cell change within it, not a change of technology), so the steps
    stay unlabelled, as the other NYU-METS files'; the other columns must be numbers."""
    text = _text(source)
    rates = []
    layout = "Mbit/s,neighbours,eNodeB_changed,RSRP,RSRQ,TA,speed,band"
    names = layout.split(",")
    for n, line in text.lines:
        fields = text.fields(n, line, separator=",", layout=layout)
        for field, name in zip(fields[1:], names[1:], strict=True):
            text.number(n, field, f"a number ({name})", minimum=-math.inf)
        rates.append(text.number(n, fields[0], "rate") * 1000.0)
    return _per_second(text, rates)
