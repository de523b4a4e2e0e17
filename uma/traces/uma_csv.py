"""uma's own trace format: a CSV of steps, `time_s,rate_kbps,technology`.

Units: seconds and kbit/s, as the column names say. Layout:

    time_s,rate_kbps,technology
    # duration_s=80.0
    0.0,812.4,3G
    1.0,0.0,

Each row starts a step of constant rate; the first starts at 0 and times increase. `technology`
may be empty (unknown) or any name `uma.traces.labels` knows (HSPA+ is read as 3G); the column
may be left out of the header altogether. Lines starting with `#` are comments; the comment
`# duration_s=X` sets where the last step ends (otherwise it lasts as long as the step before
it, or 1 s when there is only one). `write_uma_csv` writes floats exactly (Python's repr), so a
trace read back equals the trace written.
"""

from __future__ import annotations

import os
import re

from uma.atomic import atomic_write_text
from uma.errors import TraceError
from uma.traces.labels import LABELS, technology_label
from uma.traces.parsing import TraceText, shown
from uma.traces.trace import Trace

__all__ = ["read_uma_csv", "write_uma_csv", "UMA_CSV_HEADER"]

UMA_CSV_HEADER = "time_s,rate_kbps,technology"
_DIRECTIVE = re.compile(r"#\s*duration_s\s*=(.*)")


def read_uma_csv(source: str | os.PathLike | TraceText) -> Trace:
    """Read uma's CSV (see the module docstring)."""
    text = source if isinstance(source, TraceText) else TraceText(source, comments=True)
    header_number, header = text.lines[0]
    columns = [name.strip() for name in header.split(",")]
    if columns not in (["time_s", "rate_kbps", "technology"], ["time_s", "rate_kbps"]):
        raise text.error(header_number, f"expected '{UMA_CSV_HEADER}', got {shown(header)}")
    duration_s: float | None = None
    directive_line = 0
    for n, comment in text.comments:
        match = _DIRECTIVE.fullmatch(comment)
        if match is None:
            continue
        if duration_s is not None:
            raise text.error(
                n,
                f"expected one '# duration_s=' line, got a second (the first is line "
                f"{directive_line})",
            )
        duration_s = text.number(n, match.group(1), "duration in s", positive=True)
        directive_line = n
    if len(text.lines) < 2:
        raise TraceError(f"{text.name}: no samples (a header and no rows)")
    times, rates, techs, numbers = [], [], [], []
    for n, line in text.lines[1:]:
        fields = [field.strip() for field in line.split(",")]
        if not 2 <= len(fields) <= len(columns):
            raise text.error(n, f"expected '{','.join(columns)}', got {shown(line)}")
        times.append(text.number(n, fields[0], "time in s"))
        rates.append(text.number(n, fields[1], "rate in kbit/s"))
        label = technology_label(fields[2]) if len(fields) == 3 else ""
        if label is None:
            raise text.error(
                n, f"expected a technology among {', '.join(LABELS)} or empty, got {fields[2]!r}"
            )
        techs.append(label)
        numbers.append(n)
    if times[0] != 0:
        raise text.error(numbers[0], f"expected the first step at time 0, got {times[0]:g}")
    text.check_increasing(times, numbers, "s")
    if duration_s is None:
        duration_s = times[-1] + (times[-1] - times[-2] if len(times) > 1 else 1.0)
    elif not duration_s > times[-1]:
        raise text.error(
            directive_line,
            f"expected duration_s after the last step's start {times[-1]:g} s "
            f"(line {numbers[-1]}), got {duration_s:g}",
        )
    return Trace(times, rates, tuple(techs), duration_s, text.path.name)


def write_uma_csv(trace: Trace, path: str | os.PathLike) -> None:
    """Write `trace` in uma's CSV, atomically; `read_uma_csv` gives back an equal trace."""
    # One printable line, whatever the source name holds (a NUL would make the file binary).
    source = " ".join("".join(c if c.isprintable() else " " for c in trace.source).split())
    rows = [UMA_CSV_HEADER, f"# duration_s={trace.duration_s!r}", f"# source: {source}"]
    for t, rate, tech in zip(
        trace.times_s.tolist(), trace.rates_kbps.tolist(), trace.technologies, strict=True
    ):
        rows.append(f"{t!r},{rate!r},{tech}")
    atomic_write_text(path, "\n".join(rows) + "\n")
