"""Read a sweep's `sweep.csv` for the reports, checking it: a damaged table is one error line.

The table is what `uma.experiments.table.write_table` writes: point, hash, repeat, the grid's
key paths, seed, status, error, then every metric (units in the names). Anything else (a file
cut short, flipped bits, foreign bytes) is a `ConfigError` naming the file and line.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

from uma.errors import ConfigError

__all__ = ["SweepTable", "read_sweep_table", "STATUSES"]

_LEAD = ("point", "hash", "repeat")
_TAIL = ("seed", "status", "error")
# As `uma.experiments.table` writes them (missing: not run yet, the sweep is incomplete).
STATUSES = ("ok", "failed", "missing")


@dataclass(frozen=True)
class SweepTable:
    """A checked `sweep.csv`: its columns, grid keys and rows (strings, with their line)."""

    path: Path
    columns: tuple[str, ...]
    grid_keys: tuple[str, ...]
    rows: tuple[dict[str, str], ...]
    lines: tuple[int, ...]  # the file's line each row ends on

    def number(self, index: int, column: str) -> float | None:
        """Row `index`'s `column` as a number (None when empty); `ConfigError` citing the line."""
        text = self.rows[index][column]
        if text == "":
            return None
        try:
            return float(text)
        except ValueError:
            raise ConfigError(
                f"{self.path}:{self.lines[index]} ({column}): expected a number, got {text[:40]!r}"
            ) from None


def read_sweep_table(path: str | Path) -> SweepTable:
    """Read and check a sweep's CSV table; anything damaged is one `ConfigError` with its line.

    Checked: UTF-8, CSV syntax, the header (point, hash, repeat, the grid's keys, seed, status,
    error, the metrics; no name twice), every row as many fields as the header and ending in a
    newline (the writer ends every row so: a file cut short is refused, not half read), integer
    point and repeat, and a known status.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as err:
        raise ConfigError(f"{path}: cannot read ({err.strerror or err})") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data[: err.start].count(b"\n") + 1
        raise ConfigError(
            f"{path}:{line}: expected UTF-8 text, got byte 0x{data[err.start]:02x}"
        ) from None
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        header = next(reader, None)
        if not header:
            raise ConfigError(
                f"{path}:1: expected a header row {','.join(_LEAD)},...,{','.join(_TAIL)},..."
                f" (the table `uma sweep` writes), got {'an empty file' if not text else 'none'}"
            )
        _check_header(path, header)
        rows, lines = [], []
        for fields in reader:
            if len(fields) != len(header):
                raise ConfigError(
                    f"{path}:{reader.line_num}: expected {len(header)} fields, got "
                    f"{len(fields)} (the table is truncated or damaged)"
                )
            row = dict(zip(header, fields, strict=True))
            _check_row(path, reader.line_num, row)
            rows.append(row)
            lines.append(reader.line_num)
    except csv.Error as err:
        raise ConfigError(f"{path}:{reader.line_num}: malformed CSV ({err})") from None
    if not text.endswith("\n"):
        raise ConfigError(
            f"{path}:{reader.line_num}: expected every row to end with a newline, got a last row "
            f"cut short (the table is truncated)"
        )
    start, end = len(_LEAD), header.index(_TAIL[0])
    return SweepTable(path, tuple(header), tuple(header[start:end]), tuple(rows), tuple(lines))


def _check_header(path: Path, header: list[str]) -> None:
    expected = f"{path}:1: expected a header {','.join(_LEAD)},<grid keys>,{','.join(_TAIL)},..."
    if tuple(header[: len(_LEAD)]) != _LEAD or _TAIL[0] not in header:
        raise ConfigError(f"{expected}, got {','.join(header)[:80]!r}")
    at = header.index(_TAIL[0])
    if tuple(header[at : at + len(_TAIL)]) != _TAIL:
        raise ConfigError(f"{expected}, got {','.join(header)[:80]!r}")
    seen: set[str] = set()
    for name in header:
        if name in seen:
            raise ConfigError(f"{path}:1: column {name[:40]!r} given twice")
        seen.add(name)


def _check_row(path: Path, line: int, row: dict[str, str]) -> None:
    for column in ("point", "repeat"):
        if not row[column].isdigit() or not row[column].isascii():
            raise ConfigError(
                f"{path}:{line} ({column}): expected a whole number, got {row[column][:40]!r}"
            )
    if row["status"] not in STATUSES:
        raise ConfigError(
            f"{path}:{line} (status): expected one of {', '.join(STATUSES)}, "
            f"got {row['status'][:40]!r}"
        )
