"""The sweep's table: one row per run, as CSV and as Parquet (pyarrow), written atomically.

Units live in the column names, which are the metric keys of `metrics.json` (nested ones joined
by dots: `bits_sent.h264`) and the grid's key paths.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from uma.atomic import atomic_files
from uma.errors import ConfigError

__all__ = [
    "flatten",
    "cell",
    "write_table",
    "read_table_csv",
    "SweepTable",
    "read_sweep_table",
    "STATUSES",
]


def flatten(data: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Nested mappings as one level, keys joined by dots."""
    out: dict[str, Any] = {}
    for key, value in data.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out |= flatten(value, name + ".")
        else:
            out[name] = value
    return out


def cell(value: Any) -> Any:
    """A value a table column holds: scalars as they are, anything else as JSON text."""
    if value is None or isinstance(value, bool | int | float | str):
        return value
    return json.dumps(value, sort_keys=True)


def _columns(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    columns: dict[str, None] = {}
    for row in rows:
        columns |= dict.fromkeys(row)
    return list(columns)


def write_table(rows: Sequence[Mapping[str, Any]], csv_path: Path, parquet_path: Path) -> None:
    """Write `rows` to both files (same folder); a column missing from a row is empty (CSV) or null.

    Both files are written before either replaces its old version, the CSV (what `uma report`
    reads) last.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    columns = _columns(rows)
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow(["" if row.get(c) is None else row.get(c) for c in columns])
    arrays = {}
    for column in columns:
        values = [row.get(column) for row in rows]
        kinds = {type(v) for v in values if v is not None}
        if kinds <= {int, float} and float in kinds:
            values = [None if v is None else float(v) for v in values]
        elif len(kinds) > 1:
            values = [None if v is None else str(v) for v in values]
        arrays[column] = pa.array(values)
    buffer = io.BytesIO()
    pq.write_table(pa.table(arrays) if columns else pa.table({}), buffer)
    if parquet_path.parent != csv_path.parent:
        raise ValueError("write_table: expected both tables in one folder")
    atomic_files(
        csv_path.parent,
        {parquet_path.name: buffer.getvalue(), csv_path.name: text.getvalue().encode("utf-8")},
    )


def read_table_csv(path: str | Path) -> list[dict[str, str]]:
    """The CSV table's rows as strings (for plots and tests)."""
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


_LEAD = ("point", "hash", "repeat")
_TAIL = ("seed", "status", "error")
STATUSES = ("ok", "failed", "missing")  # missing: not run yet, the sweep is incomplete


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
