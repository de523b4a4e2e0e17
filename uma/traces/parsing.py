"""Reading trace files line by line, with errors that name the file and the line.

No units of its own: the readers say what each number means. Every problem with a file's text
becomes a `TraceError` worded `line 12 of foo.csv: expected ..., got ...`; nothing else escapes.

A file is read once (`TraceFile`); its format is sniffed from its first lines, and a file of one
plain number a line (Mahimahi) is parsed in one pass (`TraceFile.whole_numbers`), in memory a
few times its size instead of a list of lines some 25 times it; anything else in such a file
goes line by line (`TraceText`), which names the line.
"""

from __future__ import annotations

import codecs
import math
import os
import re
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from uma.errors import TraceError
from uma.paths import read_capped

__all__ = ["TraceFile", "TraceText", "shown", "MAX_TRACE_BYTES", "MAX_MEDIAN_STEP_S"]

# Plain decimal numbers only: float() would also take "1_000", "nan", "infinity" and spaces.
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_INTEGER = re.compile(r"\+?\d+")
_NOT_FINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)
_BOM = codecs.BOM_UTF8
_DIGITS = b"0123456789"
_BLANKS = b"\t\x0b\x0c\r "  # what str.strip() takes off an ASCII line (and \x1c-\x1f)
_SHARED_LINE = re.compile(rb"[0-9][\t\x0b\x0c\r ]+[0-9]")  # two numbers on one line


def shown(text: str, limit: int = 60) -> str:
    """`text` quoted for a message, cut to `limit` characters."""
    return repr(text if len(text) <= limit else text[:limit] + "...")


# Measured traces hold a sample every second or so (Pensieve's FCC copies every 5 s): rows a
# median of more than this apart are times in ms read as s (1000 s a row: a 300 s ride read as
# 83 hours, every rate held 1000 times too long), refused rather than stretched.
MAX_MEDIAN_STEP_S = 100.0

# A trace file, or what a gzip trace expands to, may hold at most this much text: a day of a
# fast Mahimahi trace (one line per 1,500-byte packet) is a few hundred MiB, beyond what the
# other readers' lists of lines hold comfortably (a 51 MB Mahimahi file read line by line took
# 1.3 GB); anything near it is a mistake (/dev/zero, a video).
MAX_TRACE_BYTES = 64 * 2**20


class TraceFile:
    """A trace file's bytes, read once and checked as UTF-8 text; split into lines only when a
    reader asks (`TraceText`), so a format is sniffed from a large file's first lines."""

    def __init__(self, path: str | os.PathLike) -> None:
        self.path = Path(path)
        self.name = str(path)
        # gzip: traces are often shipped compressed
        self.data = read_capped(
            path, max_bytes=MAX_TRACE_BYTES, error=TraceError, what="trace file", gunzip=True
        )
        _check_utf8(self.data, self.name)

    def decoded(self) -> str:
        """The whole text, without a leading byte-order mark."""
        return self.data.decode("utf-8-sig")

    def numbered_lines(self) -> Iterator[tuple[int, str]]:
        """(number, text) of each line as `decoded().split("\n")` has them, one at a time."""
        data = self.data
        start, number = (len(_BOM) if data.startswith(_BOM) else 0), 0
        while True:
            end = data.find(b"\n", start)
            number += 1
            if end < 0:
                yield number, data[start:].decode("utf-8")
                return
            yield number, data[start:end].decode("utf-8")
            start = end + 1

    def whole_numbers(self) -> np.ndarray | None:
        """Every line's number in one pass (int64, each exact as a float64), when each line
        holds at most one number, in plain digits (a plain Mahimahi file); else None: a sign,
        a `#`, a header or two numbers on a line are for the line-by-line reader to name."""
        data = self.data
        bom = len(_BOM) if data.startswith(_BOM) else 0
        if len(data.translate(None, _DIGITS + b"\n" + _BLANKS)) != bom:
            return None
        blanks = len(data.translate(None, _DIGITS + b"\n")) - bom
        if blanks and not _crlf_only(data, blanks) and _SHARED_LINE.search(data):
            return None
        # sep=" ": any run of blanks and line breaks separates two numbers
        numbers = np.fromstring(data[bom:] if bom else data, dtype=np.int64, sep=" ")
        if not numbers.size or numbers.max() >= 2**53:  # int64 saturates; float64 rounds
            return None
        return numbers


def _crlf_only(data: bytes, blanks: int) -> bool:
    """Whether the `blanks` bytes of `data` that are neither digits nor \\n all end a line."""
    return blanks == data.count(b"\r") == data.count(b"\r\n")


def _check_utf8(data: bytes, name: str) -> None:
    """A TraceError naming the line of the first byte that is not UTF-8 text (or is NUL)."""
    try:
        if b"\0" in data:
            raise UnicodeDecodeError("utf-8", data, data.index(b"\0"), 1, "NUL byte")
        if not data.isascii():
            data.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        line = data.count(b"\n", 0, err.start) + 1
        raise TraceError(
            f"line {line} of {name}: expected UTF-8 text, got binary data "
            f"(byte {data[err.start : err.start + 1]!r})"
        ) from None


class TraceText:
    """A trace file's numbered lines: blank lines skipped, `#` comments kept apart if allowed.

    `limit`: only the first that many data lines (what a format is sniffed from).
    """

    def __init__(
        self,
        path: str | os.PathLike | TraceFile,
        *,
        comments: bool = False,
        limit: int | None = None,
    ) -> None:
        file = path if isinstance(path, TraceFile) else TraceFile(path)
        self.path = file.path
        self.name = file.name
        self.lines: list[tuple[int, str]] = []
        self.comments: list[tuple[int, str]] = []
        # split("\n"), not splitlines(): line numbers must match what an editor shows, and
        # splitlines() also breaks at form feeds, \x1c-\x1e, U+2028 and friends.
        if limit is None:
            numbered: Iterator[tuple[int, str]] = enumerate(file.decoded().split("\n"), 1)
        else:
            numbered = file.numbered_lines()
        for number, raw in numbered:
            line = raw.strip()
            if not line:
                continue
            if comments and line.startswith("#"):
                self.comments.append((number, line))
            else:
                self.lines.append((number, line))
                if len(self.lines) == limit:
                    break
        if not self.lines:
            what = "empty file" if not file.data.strip() else "no data lines"
            raise TraceError(f"{self.name}: no samples ({what})")

    def error(self, number: int, message: str) -> TraceError:
        return TraceError(f"line {number} of {self.name}: {message}")

    def number(
        self,
        number: int,
        text: str,
        what: str,
        *,
        minimum: float = 0.0,
        positive: bool = False,
        integer: bool = False,
    ) -> float:
        """`text` as a finite number >= `minimum` (> 0 with `positive`), or a TraceError."""
        text = text.strip()
        pattern = _INTEGER if integer else _NUMBER
        if not pattern.fullmatch(text):
            if _NOT_FINITE.fullmatch(text):
                raise self.error(number, f"expected a finite {what}, got {shown(text)}")
            kind = "a whole number: " if integer else ""
            raise self.error(number, f"expected {kind}{what}, got {shown(text)}")
        value = float(text)
        if not math.isfinite(value):
            raise self.error(number, f"expected a finite {what}, got {shown(text)}")
        if positive and not value > 0:
            raise self.error(number, f"expected {what} > 0, got {shown(text)}")
        if value < minimum:
            raise self.error(number, f"expected {what} >= {minimum:g}, got {shown(text)}")
        return value + 0.0

    def fields(self, number: int, line: str, *, separator: str | None, layout: str) -> list[str]:
        """`line` split at `separator` (None: any run of blanks) into as many fields as `layout`
        names (written like `time_s,rate_kbps` or `time_s<TAB>Mbit/s`), each stripped."""
        count = len(re.split(r",|<TAB>| ", layout))
        parts = line.split(separator)
        if len(parts) != count:
            raise self.error(
                number, f"expected {count} fields '{layout}', got {len(parts)}: {shown(line)}"
            )
        return [part.strip() for part in parts]

    def check_increasing(self, times: Sequence[float], numbers: Sequence[int], unit: str) -> None:
        """A TraceError at the first line whose time is not after the one before."""
        for i in range(1, len(times)):
            if not times[i] > times[i - 1]:
                raise self.error(
                    numbers[i],
                    f"expected a time after {times[i - 1]:g} {unit} (times must increase), "
                    f"got {times[i]:g} {unit}",
                )

    def check_seconds_apart(self, times: Sequence[float], numbers: Sequence[int]) -> None:
        """A TraceError when rows are a median of more than MAX_MEDIAN_STEP_S apart (ms read
        as s), naming the first row that far from the one before."""
        if len(times) < 2:
            return
        steps = [b - a for a, b in zip(times, times[1:], strict=False)]
        median = sorted(steps)[len(steps) // 2]
        if median <= MAX_MEDIAN_STEP_S:
            return
        i = next(k for k, step in enumerate(steps) if step >= median) + 1
        raise self.error(
            numbers[i],
            f"expected times in s, rows seconds apart; got rows a median {median:g} s apart "
            f"({times[i - 1]:.15g} then {times[i]:.15g}): are the times in ms?",
        )
