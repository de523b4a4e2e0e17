"""Reader for technology-labelled CSV logs (G-NetTrack, as in Raca et al.'s UCC 5G dataset).

Units: `DL_bitrate` in kbit/s, `Timestamp` to the second (`2019.12.02_09.39.35`, read as UTC:
only differences matter, and no daylight-saving jump can reorder rows); the `Trace` is in
seconds and kbit/s. A row's rate and `NetworkMode` hold from its time stamp until the next
row's (a missing second keeps the row before), the last row for one second. `NetworkMode` is
normalised (HSPA+/HSDPA/HSUPA/UMTS -> 3G; GPRS, EDGE, LTE, 5G kept; "-" -> unknown ""); a mode
that names no technology is an error, never silently dropped.

The logger writes about one row a second but sometimes two or three in the same second (in the
shared files mostly repeated readings: 4 of 47 duplicates differ in B_2019.12.02). Rows sharing
a time stamp are a group that holds until the next stamp:
- `duplicates="mean"` (default): one step at the mean rate, when the rows agree on the mode;
  rows that disagree (a handover within the second) are split as below, never merged;
- `duplicates="split"`: the group's time is shared equally, one step per row, in file order.
Without a `Timestamp` column, rows are one second apart.
"""

from __future__ import annotations

import os
import re
from datetime import datetime, timezone

import numpy as np

from uma.errors import TraceError
from uma.traces.labels import LABELS, technology_label
from uma.traces.parsing import TraceText, shown
from uma.traces.trace import Trace

__all__ = ["read_labelled_csv", "DUPLICATE_MODES"]

DUPLICATE_MODES = ("mean", "split")
_STAMP = re.compile(r"\d{4}\.\d{2}\.\d{2}_\d{2}\.\d{2}\.\d{2}")


def _stamp_s(text: TraceText, number: int, field: str) -> float:
    if _STAMP.fullmatch(field):
        try:
            moment = datetime.strptime(field, "%Y.%m.%d_%H.%M.%S")
        except ValueError:
            pass
        else:
            return moment.replace(tzinfo=timezone.utc).timestamp()
        raise text.error(number, f"expected a real date and time in Timestamp, got {shown(field)}")
    if field and (field[0].isdigit() or field[0] == "."):
        return text.number(number, field, "Timestamp in s")
    raise text.error(
        number, f"expected a Timestamp like 2019.12.02_09.39.35 or seconds, got {shown(field)}"
    )


def _columns(text: TraceText) -> tuple[int, int, int | None, int]:
    """(NetworkMode's, DL_bitrate's, Timestamp's or None, how many columns) from the header."""
    header_number, header = text.lines[0]
    columns = [name.strip() for name in header.split(",")]
    missing = [name for name in ("NetworkMode", "DL_bitrate") if name not in columns]
    if missing:
        raise text.error(
            header_number,
            f"expected a header naming NetworkMode and DL_bitrate, got {shown(header)}",
        )
    i_time = columns.index("Timestamp") if "Timestamp" in columns else None
    return columns.index("NetworkMode"), columns.index("DL_bitrate"), i_time, len(columns)


def _groups(text: TraceText) -> list[tuple[float, list[tuple[float, str]], int]]:
    """The rows grouped by time stamp: [(stamp_s, [(rate_kbps, label), ...], line number of
    the group's first row)], stamps rising."""
    i_mode, i_rate, i_time, width = _columns(text)
    if len(text.lines) < 2:
        raise TraceError(f"{text.name}: no samples (a header and no rows)")
    groups: list[tuple[float, list[tuple[float, str]], int]] = []
    for row, (n, line) in enumerate(text.lines[1:]):
        fields = line.split(",")
        if len(fields) != width:
            raise text.error(
                n,
                f"expected {width} comma-separated fields as in the header, "
                f"got {len(fields)}: {shown(line)}",
            )
        stamp = _stamp_s(text, n, fields[i_time].strip()) if i_time is not None else float(row)
        rate = text.number(n, fields[i_rate], "DL_bitrate in kbit/s")
        label = technology_label(fields[i_mode])
        if label is None:
            raise text.error(
                n,
                f"expected a NetworkMode naming a technology ({', '.join(LABELS)}, HSPA+, "
                f"HSDPA, UMTS, ...) or '-', got {shown(fields[i_mode].strip())}",
            )
        if groups and stamp == groups[-1][0]:
            groups[-1][1].append((rate, label))
            continue
        if groups and not stamp > groups[-1][0]:
            raise text.error(
                n,
                f"expected a Timestamp not before the row at line {groups[-1][2]} "
                f"(times must not go back), got {fields[i_time].strip()}",
            )
        groups.append((stamp, [(rate, label)], n))
    return groups


def read_labelled_csv(source: str | os.PathLike | TraceText, *, duplicates: str = "mean") -> Trace:
    """A labelled CSV log as a trace with one technology per step (see the module docstring)."""
    if duplicates not in DUPLICATE_MODES:
        raise TraceError(
            f"labelled-csv duplicates: expected one of {', '.join(DUPLICATE_MODES)}, "
            f"got {duplicates!r}"
        )
    text = source if isinstance(source, TraceText) else TraceText(source)
    groups = _groups(text)
    text.check_seconds_apart([stamp for stamp, _, _ in groups], [n for _, _, n in groups])
    origin = groups[0][0]
    starts: list[float] = []
    rates: list[float] = []
    labels: list[str] = []
    for k, (stamp, rows, _) in enumerate(groups):
        span = groups[k + 1][0] - stamp if k + 1 < len(groups) else 1.0
        kinds = {label for _, label in rows}
        if duplicates == "mean" and len(kinds) == 1:
            starts.append(stamp - origin)
            rates.append(float(np.mean([rate for rate, _ in rows])))
            labels.append(rows[0][1])
            continue
        for j, (rate, label) in enumerate(rows):
            starts.append(stamp - origin + span * j / len(rows))
            rates.append(rate)
            labels.append(label)
    end = groups[-1][0] - origin + 1.0
    return Trace(np.array(starts), np.array(rates), tuple(labels), end, text.path.name)
