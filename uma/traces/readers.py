"""Readers for the bandwidth-trace formats users already have, and uma's own CSV.

Units: every reader returns a `Trace` in seconds and kbit/s. Errors are `TraceError`s naming the
file and the 1-based line, with what was expected and what was found.

| format         | lines                                   | note                                  |
|----------------|-----------------------------------------|---------------------------------------|
| uma-csv        | `time_s,rate_kbps,technology` header    | `# duration_s=X` comment sets the end  |
| mahimahi       | one ms timestamp per 1500-byte delivery | binned into `bin_ms` steps             |
| pensieve       | `time_s<TAB>Mbit/s`                     | times re-based to the first            |
| hsdpa-log      | `unix_s ms lat lon bytes interval_ms`   | stops where the ms counter resets      |
| labelled-csv   | header with `NetworkMode`, `DL_bitrate` | kbit/s, 1 row/s; duplicate stamps meaned |
| bytes-per-sec  | `sec,bytes_per_sec`                     |                                        |
| nyu-mets       | `value,unit` (Mbits/sec, Kbits/sec, ...) | one sample per second                 |
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from datetime import datetime
from pathlib import Path

import numpy as np

from uma.atomic import atomic_write_text
from uma.errors import TraceError
from uma.traces.technology import normalise_technology
from uma.traces.trace import Trace

__all__ = ["read_trace", "write_uma_csv", "FORMATS", "sniff_format"]

MAHIMAHI_PACKET_BITS = 1500 * 8


def _lines(path: Path) -> list[tuple[int, str]]:
    """Numbered non-blank lines, without `#` comments; a missing or binary file is a TraceError."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise TraceError(f"{path}: no such trace file") from None
    except UnicodeDecodeError:
        raise TraceError(f"{path}: not a text file (expected a bandwidth trace)") from None
    except OSError as err:
        raise TraceError(f"{path}: cannot read ({err.strerror})") from None
    out = [(n, line.strip()) for n, line in enumerate(text.splitlines(), 1)]
    out = [(n, line) for n, line in out if line and not line.startswith("#")]
    if not out:
        raise TraceError(f"{path}: no samples")
    return out


def _number(path: Path, lineno: int, text: str, what: str, *, minimum: float = 0.0) -> float:
    try:
        value = float(text)
    except ValueError:
        raise TraceError(f"line {lineno} of {path}: expected {what}, got {text!r}") from None
    if not math.isfinite(value) or value < minimum:
        raise TraceError(f"line {lineno} of {path}: expected {what} >= {minimum:g}, got {text!r}")
    return value


def _from_samples(
    path: Path,
    times: list[float],
    rates: list[float],
    techs: list[str],
    lines: list[int],
    *,
    last_step_s: float | None = None,
) -> Trace:
    """Re-base to the first time, check order, and close the last step."""
    if not times:
        raise TraceError(f"{path}: no samples")
    t = np.asarray(times, dtype=np.float64) - times[0]
    steps = np.diff(t)
    if np.any(steps <= 0):
        bad = int(np.flatnonzero(steps <= 0)[0]) + 1
        raise TraceError(
            f"line {lines[bad]} of {path}: expected a time after {times[bad - 1]:g}, "
            f"got {times[bad]:g}"
        )
    if last_step_s is None:
        last_step_s = float(np.median(steps)) if steps.size else 1.0
    return Trace(t, np.asarray(rates), tuple(techs), float(t[-1] + last_step_s), path.name)


def read_uma_csv(path: Path) -> Trace:
    lines = _lines(path)
    header_n, header = lines[0]
    columns = [c.strip() for c in header.split(",")]
    if columns not in (["time_s", "rate_kbps"], ["time_s", "rate_kbps", "technology"]):
        raise TraceError(
            f"line {header_n} of {path}: expected 'time_s,rate_kbps,technology', got {header!r}"
        )
    duration_s = None
    for raw in path.read_text(encoding="utf-8").splitlines():
        if raw.strip().startswith("# duration_s="):
            duration_s = _number(path, 0, raw.split("=", 1)[1].strip(), "a duration in s")
    times, rates, techs, numbers = [], [], [], []
    for n, line in lines[1:]:
        fields = [f.strip() for f in line.split(",")]
        if len(fields) not in (2, 3) or len(fields) > len(columns):
            raise TraceError(
                f"line {n} of {path}: expected 'time_s,rate_kbps,technology', got {line!r}"
            )
        times.append(_number(path, n, fields[0], "a time in s"))
        rates.append(_number(path, n, fields[1], "a rate in kbit/s"))
        techs.append(normalise_technology(fields[2]) if len(fields) == 3 else "")
        numbers.append(n)
    if times and times[0] != 0:
        raise TraceError(
            f"line {numbers[0]} of {path}: expected the first step at time 0, got {times[0]:g}"
        )
    last = None if duration_s is None or not times else duration_s - times[-1]
    if last is not None and last <= 0:
        raise TraceError(f"{path}: duration_s={duration_s:g} does not cover the last step")
    return _from_samples(path, times, rates, techs, numbers, last_step_s=last)


def write_uma_csv(trace: Trace, path: str | os.PathLike) -> None:
    """Write `trace` in uma's CSV (atomically); `read_trace` gives it back exactly."""
    rows = ["time_s,rate_kbps,technology", f"# duration_s={trace.duration_s!r}"]
    for t, r, tech in zip(
        trace.times_s.tolist(), trace.rates_kbps.tolist(), trace.technologies, strict=True
    ):
        rows.append(f"{t!r},{r!r},{tech}")
    atomic_write_text(path, "\n".join(rows) + "\n")


def read_mahimahi(path: Path, *, bin_ms: float = 500.0) -> Trace:
    """Mahimahi: each line is the ms at which one 1500-byte packet may be delivered.

    Opportunities are counted in `bin_ms` bins (default 500 ms: fine enough to follow fades,
    coarse enough that one opportunity more or less moves a 100 kbit/s link by only 24 %).
    """
    stamps, numbers = [], []
    for n, line in _lines(path):
        stamps.append(_number(path, n, line, "a delivery time in ms"))
        numbers.append(n)
    ms = np.asarray(stamps)
    if np.any(np.diff(ms) < 0):
        bad = int(np.flatnonzero(np.diff(ms) < 0)[0]) + 1
        raise TraceError(
            f"line {numbers[bad]} of {path}: expected a time not before {stamps[bad - 1]:g} ms, got {stamps[bad]:g}"
        )
    bins = int(ms[-1] // bin_ms) + 1
    counts = np.bincount((ms // bin_ms).astype(np.int64), minlength=bins)
    rates = counts * MAHIMAHI_PACKET_BITS / bin_ms  # bits per ms = kbit/s
    times = np.arange(bins) * bin_ms / 1000.0
    return Trace(times, rates, ("",) * bins, bins * bin_ms / 1000.0, path.name)


def read_pensieve(path: Path) -> Trace:
    times, rates, numbers = [], [], []
    for n, line in _lines(path):
        fields = line.split()
        if len(fields) != 2:
            raise TraceError(f"line {n} of {path}: expected 'time_s<TAB>Mbit/s', got {line!r}")
        times.append(_number(path, n, fields[0], "a time in s"))
        rates.append(1000.0 * _number(path, n, fields[1], "a rate in Mbit/s"))
        numbers.append(n)
    return _from_samples(path, times, rates, [""] * len(times), numbers)


def read_hsdpa_log(path: Path) -> Trace:
    """Riiser et al.'s raw log; a copy that repeats the log stops where the ms counter resets."""
    times, rates, numbers = [], [], []
    last_interval_s = 1.0
    for n, line in _lines(path):
        fields = line.split()
        if len(fields) != 6:
            raise TraceError(
                f"line {n} of {path}: expected 'unix_s ms_since_start lat lon bytes interval_ms', got {line!r}"
            )
        ms = _number(path, n, fields[1], "milliseconds since start")
        if times and ms / 1000.0 <= times[-1]:
            break  # the counter reset: the log repeats from here
        size_bytes = _number(path, n, fields[4], "a byte count")
        interval_ms = _number(path, n, fields[5], "an interval in ms", minimum=1e-9)
        times.append(ms / 1000.0)
        rates.append(size_bytes * 8.0 / interval_ms)  # bits per ms = kbit/s
        numbers.append(n)
        last_interval_s = interval_ms / 1000.0
    return _from_samples(
        path, times, rates, [""] * len(times), numbers, last_step_s=last_interval_s
    )


def read_labelled_csv(path: Path) -> Trace:
    """Raca et al.'s CSV: `Timestamp` (YYYY.MM.DD_HH.MM.SS), `NetworkMode`, `DL_bitrate` in kbit/s."""
    lines = _lines(path)
    header_n, header = lines[0]
    columns = [c.strip() for c in header.split(",")]
    try:
        i_time, i_mode, i_rate = (
            columns.index(c) for c in ("Timestamp", "NetworkMode", "DL_bitrate")
        )
    except ValueError:
        raise TraceError(
            f"line {header_n} of {path}: expected a header with Timestamp, NetworkMode and DL_bitrate"
        ) from None
    seconds: list[float] = []
    sums: list[float] = []
    counts: list[int] = []
    techs: list[str] = []
    numbers: list[int] = []
    for n, line in lines[1:]:
        fields = line.split(",")
        if len(fields) != len(columns):
            raise TraceError(
                f"line {n} of {path}: expected {len(columns)} fields, got {len(fields)}"
            )
        try:
            stamp = datetime.strptime(fields[i_time].strip(), "%Y.%m.%d_%H.%M.%S").timestamp()
        except ValueError:
            raise TraceError(
                f"line {n} of {path}: expected Timestamp like 2019.12.02_09.39.35, got {fields[i_time]!r}"
            ) from None
        rate = _number(path, n, fields[i_rate].strip(), "DL_bitrate in kbit/s")
        if seconds and stamp == seconds[-1]:
            sums[-1] += rate
            counts[-1] += 1
            continue
        seconds.append(stamp)
        sums.append(rate)
        counts.append(1)
        techs.append(normalise_technology(fields[i_mode].strip()))
        numbers.append(n)
    rates = [s / c for s, c in zip(sums, counts, strict=True)]
    return _from_samples(path, seconds, rates, techs, numbers, last_step_s=1.0)


def read_bytes_per_sec(path: Path) -> Trace:
    times, rates, numbers = [], [], []
    for n, line in _lines(path):
        fields = line.split(",")
        if len(fields) != 2:
            raise TraceError(f"line {n} of {path}: expected 'sec,bytes_per_sec', got {line!r}")
        times.append(_number(path, n, fields[0], "a time in s"))
        rates.append(_number(path, n, fields[1], "bytes per second") * 8.0 / 1000.0)
        numbers.append(n)
    return _from_samples(path, times, rates, [""] * len(times), numbers, last_step_s=1.0)


NYU_UNITS_KBPS = {"mbits/sec": 1000.0, "kbits/sec": 1.0, "bits/sec": 0.001}


def read_nyu_mets(path: Path) -> Trace:
    rates, numbers = [], []
    for n, line in _lines(path):
        fields = [f.strip() for f in line.split(",")]
        if len(fields) != 2 or fields[1].lower() not in NYU_UNITS_KBPS:
            raise TraceError(
                f"line {n} of {path}: expected 'value,unit' with unit Mbits/sec, Kbits/sec or bits/sec, got {line!r}"
            )
        rates.append(_number(path, n, fields[0], "a rate") * NYU_UNITS_KBPS[fields[1].lower()])
        numbers.append(n)
    return _from_samples(
        path,
        [float(i) for i in range(len(rates))],
        rates,
        [""] * len(rates),
        numbers,
        last_step_s=1.0,
    )


FORMATS: dict[str, Callable[[Path], Trace]] = {
    "uma-csv": read_uma_csv,
    "mahimahi": read_mahimahi,
    "pensieve": read_pensieve,
    "hsdpa-log": read_hsdpa_log,
    "labelled-csv": read_labelled_csv,
    "bytes-per-sec": read_bytes_per_sec,
    "nyu-mets": read_nyu_mets,
}


def sniff_format(path: Path) -> str:
    """Guess a trace's format from its first data line (see the table above)."""
    lines = _lines(path)
    first = lines[0][1]
    if first.replace(" ", "").startswith("time_s"):
        return "uma-csv"
    if "NetworkMode" in first and "DL_bitrate" in first:
        return "labelled-csv"
    comma = first.split(",")
    blank = first.split()
    if len(blank) == 1 and len(comma) == 1 and first.isdigit():
        return "mahimahi"
    if len(comma) == 2 and any(c.isalpha() for c in comma[1]):
        return "nyu-mets"
    if len(comma) == 2:
        return "bytes-per-sec"
    if len(blank) == 2:
        return "pensieve"
    if len(blank) == 6:
        return "hsdpa-log"
    raise TraceError(
        f"line {lines[0][0]} of {path}: cannot tell the trace format from {first[:60]!r}; "
        f"give one of {', '.join(FORMATS)}"
    )


def read_trace(path: str | os.PathLike, *, format: str = "auto") -> Trace:
    """Read a trace in `format` (one of `FORMATS`), or guess it with `format="auto"`."""
    path = Path(path)
    if format == "auto":
        format = sniff_format(path)
    reader = FORMATS.get(format)
    if reader is None:
        raise TraceError(
            f"{path}: unknown trace format {format!r}; expected auto or one of {', '.join(FORMATS)}"
        )
    return reader(path)
