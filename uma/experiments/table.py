"""The sweep's table: one row per run, as CSV and as Parquet (pyarrow), written atomically.

Units live in the column names, which are the metric keys of `metrics.json` (nested ones joined
by dots: `bits_sent.h264`) and the grid's key paths.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from uma.atomic import atomic_files

__all__ = [
    "flatten",
    "cell",
    "write_table",
    "read_table_csv",
    "STATUSES",
]


STATUSES = ("ok", "failed", "missing")  # missing: not run yet, the sweep is incomplete


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
