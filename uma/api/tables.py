"""A run's CSV files as pandas DataFrames, parsed from the very bytes `uma run` writes.

Column names are the CSV's, units in them (`capture_ms`, `size_bits`, `rate_kbps`, ...). Each
column of `frames.csv` gets the type the frame log gives it (`uma.metrics.framelog.COLUMNS`):
integers as int64, times and qualities as float64 with NaN where the CSV cell is empty, and
the text columns (`technology`, `codec`, `shown_codec`) as str with "" where empty. A column
the log does not know (a newer uma) is typed by pandas.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING

from uma.errors import ConfigError

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["frames_frame", "events_frame", "sweep_frame"]


def _header(data: bytes, where: Path) -> list[str]:
    first = data.split(b"\n", 1)[0].decode("utf-8", errors="replace").strip()
    if not first:
        raise ConfigError(f"{where}: expected a CSV header line, got an empty file")
    return first.split(",")


def frames_frame(data: bytes, where: Path) -> pd.DataFrame:
    """`frames.csv` bytes as a DataFrame typed as the frame log types its columns."""
    import pandas as pd

    from uma.metrics.framelog import COLUMNS

    dtypes, missing = {}, {}
    for name in _header(data, where):
        kind = COLUMNS[name][0][0] if name in COLUMNS else None
        if kind == "U":
            dtypes[name] = str
        elif kind is not None:
            dtypes[name] = "float64" if kind == "f" else "int64"
            missing[name] = [""]
    try:
        return pd.read_csv(io.BytesIO(data), dtype=dtypes, keep_default_na=False, na_values=missing)
    except (ValueError, pd.errors.ParserError) as err:
        raise ConfigError(f"{where}: expected the frames.csv of a finished run ({err})") from None


def events_frame(data: bytes, where: Path) -> pd.DataFrame:
    """`events.csv` bytes as a DataFrame: `time_ms` (float64), `kind` and `detail` (str)."""
    import pandas as pd

    try:
        frame = pd.read_csv(
            io.BytesIO(data),
            dtype={"time_ms": "float64", "kind": str, "detail": str},
            keep_default_na=False,
            na_values={"time_ms": [""]},
        )
    except (ValueError, pd.errors.ParserError) as err:
        raise ConfigError(f"{where}: expected the events.csv of a finished run ({err})") from None
    if list(frame.columns) != ["time_ms", "kind", "detail"]:
        raise ConfigError(
            f"{where}: expected columns time_ms,kind,detail, got {list(frame.columns)}"
        )
    return frame


def sweep_frame(path: Path) -> pd.DataFrame:
    """A sweep's `sweep.parquet` as a DataFrame; `ConfigError` naming the file if unreadable."""
    import stat

    import pandas as pd
    import pyarrow

    try:
        if not stat.S_ISREG(path.stat().st_mode):  # a FIFO would block the reader
            raise ConfigError(f"{path}: expected a sweep table in Parquet, got a folder or device")
        return pd.read_parquet(path, engine="pyarrow")
    except FileNotFoundError:
        raise ConfigError(
            f"{path.parent}: expected a sweep's results folder (as `uma sweep` writes), "
            f"found no {path.name}"
        ) from None
    except (OSError, pyarrow.ArrowException, ValueError) as err:
        raise ConfigError(f"{path}: expected a sweep table in Parquet ({err})") from None
