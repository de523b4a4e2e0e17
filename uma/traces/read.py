"""One entry point for every trace format: `read_trace(path, format="auto")`.

Units: the `Trace` returned is in seconds and kbit/s whatever the file's units.

| format         | lines                                        | reader                          |
|----------------|----------------------------------------------|---------------------------------|
| uma-csv        | `time_s,rate_kbps,technology` header, `#`    | `uma.traces.uma_csv`            |
| mahimahi       | one ms time stamp per 1500-byte opportunity  | binned, `bin_ms` (100 ms)       |
| pensieve       | `time_s<TAB>Mbit/s`                          |                                 |
| hsdpa-log      | `unix_s ms_since_start lat lon bytes interval_ms` | stops where the log restarts |
| labelled-csv   | header with `NetworkMode`, `DL_bitrate` kbit/s | `duplicates` ("mean", "split") |
| bytes-per-sec  | `sec,bytes_per_sec`                          |                                 |
| nyu-mets       | `value,unit` (Mbits/sec, Kbits/sec, bits/sec) | one row a second               |
| nyu-mets-multivariate | eight numbers, the first Mbit/s (BB62.txt.gz) | one row a second, rate only |

`format="auto"` looks at the first data lines (all of the first five must agree), and falls back
on the file name (`*.down`, `*.up`: Mahimahi) so a broken Mahimahi file gets the Mahimahi
reader's exact complaint. A header row over a format that has none (`time_s,Mbit/s`,
`sec<TAB>bytes_per_sec`) is skipped when the units its column names say are the format's, and
refused at line 1 when not (`uma.traces.header`); it also tells a two-column file's unit
(Mbit/s or bytes/s) where the numbers alone cannot. Without a header, a two-column file whose
rates do not fit its format's unit is refused naming its fastest row, and rows a median of more
than 100 s apart are refused as times in ms (`TraceText.check_seconds_apart`).
"""

from __future__ import annotations

import os
from collections.abc import Callable

from uma.errors import TraceError
from uma.traces.header import HEADER_COLUMNS, check_header, column_unit, is_header
from uma.traces.labelled import read_labelled_csv
from uma.traces.parsing import TraceFile, TraceText, shown
from uma.traces.readers import (
    read_bytes_per_sec,
    read_hsdpa_log,
    read_mahimahi,
    read_nyu_mets,
    read_nyu_mets_multivariate,
    read_pensieve,
    read_plain_mahimahi,
)
from uma.traces.trace import Trace
from uma.traces.uma_csv import read_uma_csv

__all__ = ["FORMATS", "read_trace", "sniff_format"]

FORMATS: dict[str, Callable[..., Trace]] = {
    "mahimahi": read_mahimahi,
    "pensieve": read_pensieve,
    "hsdpa-log": read_hsdpa_log,
    "labelled-csv": read_labelled_csv,
    "bytes-per-sec": read_bytes_per_sec,
    "nyu-mets": read_nyu_mets,
    "nyu-mets-multivariate": read_nyu_mets_multivariate,
    "uma-csv": read_uma_csv,
}
_OPTIONS = {"mahimahi": {"bin_ms"}, "labelled-csv": {"duplicates"}}
_NAME_HINTS = {".down": "mahimahi", ".up": "mahimahi"}
_HEAD = 6  # the data lines a format is sniffed from (`_sniff`)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _shape(line: str) -> str | None:
    """The format one data line looks like, or None."""
    if line.isascii() and line.isdigit():
        return "mahimahi"
    commas = [field.strip() for field in line.split(",")]
    if len(commas) == 8 and all(_is_number(field) for field in commas):
        return "nyu-mets-multivariate"
    if len(commas) == 2 and _is_number(commas[0]):
        if _is_number(commas[1]):
            return "bytes-per-sec"
        if commas[1].lower().endswith("bits/sec"):
            return "nyu-mets"
        return None
    blanks = line.split()
    if all(_is_number(field) for field in blanks):
        return {2: "pensieve", 6: "hsdpa-log"}.get(len(blanks))
    return None


def _sniff(text: TraceText) -> tuple[str, str | None]:
    """(format, the header line over rows of a header-less format, or None)."""
    first_number, first = text.lines[0]
    columns = [name.strip() for name in first.split(",")]
    # uma's header, maybe misspelt (its reader says how), unless it names another rate unit
    if columns[0] == "time_s" and column_unit(columns[-1]) in (None, "kbit/s", "s"):
        return "uma-csv", None
    if "NetworkMode" in columns and "DL_bitrate" in columns:
        return "labelled-csv", None
    shapes = {_shape(line) for _, line in text.lines[:5]}
    if len(shapes) == 1 and None not in shapes:
        return shapes.pop(), None
    below = {_shape(line) for _, line in text.lines[1:6]}
    if is_header(first) and len(below) == 1 and None not in below:
        shape = below.pop()
        if shape in ("pensieve", "bytes-per-sec"):  # the header's unit picks, not the commas
            names = first.split("," if "," in first else None)
            unit = column_unit(names[-1]) if len(names) == 2 else None
            shape = {"Mbit/s": "pensieve", "bytes/s": "bytes-per-sec"}.get(unit or "", shape)
        return shape, first
    hint = _NAME_HINTS.get(text.path.suffix.lower())
    if hint is not None:
        return hint, None
    raise TraceError(
        f"line {first_number} of {text.name}: cannot tell the trace format from "
        f"{shown(first)}; expected one of the formats {', '.join(FORMATS)} "
        f"(a scenario's route segment may name it: format: NAME)"
    )


def sniff_format(path: str | os.PathLike) -> str:
    """The name of the format `path` is written in (a key of `FORMATS`), or a TraceError."""
    return _sniff(TraceText(path, comments=True, limit=_HEAD))[0]


def read_trace(path: str | os.PathLike, *, format: str = "auto", **options: object) -> Trace:
    """Read a trace in `format` (a key of `FORMATS`, or "auto" to sniff it).

    `options` go to the reader: `bin_ms` for mahimahi, `duplicates` for labelled-csv.
    """
    if format != "auto" and format not in FORMATS:
        raise TraceError(
            f"{path}: unknown trace format {format!r}; expected auto or one of {', '.join(FORMATS)}"
        )
    file = TraceFile(path)
    head = TraceText(file, comments=True, limit=_HEAD)
    sniffed = format == "auto"
    if sniffed:
        format, _ = _sniff(head)
    unknown = set(options) - _OPTIONS.get(format, set())
    if unknown:
        allowed = ", ".join(sorted(_OPTIONS.get(format, ()))) or "none"
        raise TraceError(
            f"{path}: format {format} takes no option {', '.join(sorted(unknown))} "
            f"(its options: {allowed})"
        )
    if format == "mahimahi":
        # one pass over a plain file: its lines are never split into a list
        trace = read_plain_mahimahi(file, **options)
        if trace is not None:
            return trace
    # Only uma's own format has comments: elsewhere a '#' line is a malformed line.
    text = TraceText(file, comments=format == "uma-csv")
    header = _strip_header(text, format)
    if sniffed and header is None:
        _check_plausible(text, format)
    return FORMATS[format](text, **options)


def _strip_header(text: TraceText, format: str) -> str | None:
    """Take a header row off a format that has none (checked against it), and return it."""
    number, first = text.lines[0]
    if format not in HEADER_COLUMNS or len(text.lines) < 2 or not is_header(first):
        return None
    check_header(text, number, first, format, HEADER_COLUMNS[format])
    text.lines = text.lines[1:]
    return first


# Sniffed by their separator alone, a `time_s,Mbit/s` file would be read as bytes per second
# (125,000 times too slow) and `sec<TAB>bytes_per_sec` as Mbit/s: rates no link has are refused.
# The fastest second under 1,000 bytes (8 kbit/s) is Mbit/s written with commas; over 10 Gbit/s,
# bytes per second written with a tab. A dead link (every row 0) is read as it is.
_MAX_PENSIEVE_MBPS = 1e4


def _fastest_row(text: TraceText) -> tuple[float, int, str]:
    """(the largest second column, its line number, the line) of a two-column file; a row
    that does not read is left to the reader, which names it."""
    top, where = -1.0, text.lines[0]
    for n, line in text.lines:
        fields = line.split("," if "," in line else None)
        try:
            value = float(fields[1]) if len(fields) == 2 else -1.0
        except ValueError:
            continue
        if value > top:  # NaN never is
            top, where = value, (n, line)
    return top, where[0], where[1]


def _check_plausible(text: TraceText, format: str) -> None:
    """A TraceError naming the fastest row when a two-column trace's rates say its unit is
    not the one its separator chose."""
    if format not in ("bytes-per-sec", "pensieve"):
        return
    top, number, line = _fastest_row(text)
    if format == "bytes-per-sec" and 0 < top < 1000:
        raise text.error(
            number,
            f"expected sec,bytes_per_sec (commas), whose fastest row should carry 1,000 bytes "
            f"or more (8 kbit/s); got at most {top:g} bytes in a second ({shown(line)}); if the "
            f"rates are Mbit/s, name the unit in a header row: time_s,Mbit/s",
        )
    if format == "pensieve" and top > _MAX_PENSIEVE_MBPS:
        raise text.error(
            number,
            f"expected time_s<TAB>Mbit/s (blanks), at most 10 Gbit/s; got {top:g} Mbit/s "
            f"({shown(line)}); if the rates are bytes per second, name the unit in a "
            f"header row: sec<TAB>bytes_per_sec",
        )
