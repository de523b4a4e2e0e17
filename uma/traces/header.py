"""A header row over a format that has none (`time_s<TAB>Mbps`, `sec,bytes_per_sec`, `value,unit`):
recognised, skipped, and checked against what the format's columns hold.

Units: a column's name may name a unit (`time_ms`, `Mbit/s`, `BytesPerSecond`, `kbps`); where it
does, it must be the unit the format reads there, or the file is refused naming the header line:
a header saying kbit/s over a column read as bytes/s would otherwise be a rate off by 8.
"""

from __future__ import annotations

import re

from uma.traces.parsing import TraceText, shown

__all__ = ["is_header", "column_unit", "check_header", "COLUMN_UNITS", "HEADER_COLUMNS"]

# The formats without a header of their own, and how many columns their rows have.
HEADER_COLUMNS = {
    "mahimahi": 1,
    "pensieve": 2,
    "hsdpa-log": 6,
    "bytes-per-sec": 2,
    "nyu-mets": 2,
    "nyu-mets-multivariate": 8,
}
# What the header-less formats hold, column by column (0-based), where a header could say.
COLUMN_UNITS: dict[str, dict[int, str]] = {
    "mahimahi": {0: "ms"},
    "pensieve": {0: "s", 1: "Mbit/s"},
    "bytes-per-sec": {0: "s", 1: "bytes/s"},
    "nyu-mets-multivariate": {0: "Mbit/s"},
    "hsdpa-log": {1: "ms", 5: "ms"},
}
_WORDS = re.compile(r"[A-Za-z]+")
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|[+-]?(?:nan|inf)", re.IGNORECASE)
_BYTES = {"B": "bytes/s", "kB": "kB/s", "KB": "kB/s", "MB": "MB/s", "GB": "GB/s"}
_UNITS = {
    **{word: "s" for word in ("s", "sec", "secs", "second", "seconds")},
    **{word: "ms" for word in ("ms", "msec", "msecs", "millis", "millisecond", "milliseconds")},
    **{word: "us" for word in ("us", "usec", "microsecond", "microseconds")},
    **{word: "bit/s" for word in ("bps", "bit", "bits")},
    **{word: "kbit/s" for word in ("kbps", "kbit", "kbits", "kb")},
    **{word: "Mbit/s" for word in ("mbps", "mbit", "mbits", "mb")},
    **{word: "Gbit/s" for word in ("gbps", "gbit", "gbits", "gb")},
    **{word: "bytes/s" for word in ("byte", "bytes")},
}
_INFIXES = (("byte", "bytes/s"), ("millisec", "ms"), ("second", "s"))  # camelCase names


def is_header(line: str) -> bool:
    """A row of column names: letters, no field a number, and not a `#` comment."""
    if line.startswith("#") or not _WORDS.search(line):
        return False
    return not any(_NUMBER.fullmatch(field) for field in re.split(r"[,;\s]+", line) if field)


def column_unit(name: str) -> str | None:
    """The unit a column's name states (`time_ms` -> ms, `Mbit/s` -> Mbit/s), or None."""
    units = []
    for word in _WORDS.findall(name):
        unit = _BYTES.get(word.removesuffix("ps")) or _UNITS.get(word.lower())
        if unit is None:
            unit = next((u for infix, u in _INFIXES if infix in word.lower()), None)
        if unit is not None:
            units.append(unit)
    rates = [unit for unit in units if unit not in ("s", "ms", "us")]
    return (rates or units or [None])[0]  # a rate unit wins over `per_sec` in `bytes_per_sec`


def check_header(text: TraceText, number: int, header: str, fmt: str, columns: int) -> None:
    """A TraceError at the header when its column count or a unit it names is not `fmt`'s."""
    separator = "," if "," in header else "\t" if "\t" in header else None
    names = [name.strip() for name in header.split(separator)]
    if len(names) != columns:
        raise text.error(
            number,
            f"expected a header of {columns} columns like the rows after it ({fmt}), "
            f"got {len(names)}: {shown(header)}",
        )
    for index, expected in COLUMN_UNITS.get(fmt, {}).items():
        unit = column_unit(names[index])
        if unit is not None and unit != expected:
            raise text.error(
                number,
                f"expected column {index + 1} of the header in {expected}, as {fmt} rows hold "
                f"it, got {shown(names[index])} ({unit}); write other units as uma's CSV "
                f"(time_s,rate_kbps,technology)",
            )
