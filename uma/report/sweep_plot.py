"""A sweep's summary plot: one metric against one grid key, a line per combination of the others.

Units: those of the metric's and the key's names. Repeats (seeds) of a point are averaged and
their range drawn as a band; failed points are left out (and counted in the title).
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np

from uma.errors import ConfigError

__all__ = ["draw_sweep_summary", "grid_keys_of"]


def grid_keys_of(columns: list[str]) -> list[str]:
    """The grid's key paths: the table's columns between `repeat` and `seed`."""
    try:
        return columns[columns.index("repeat") + 1 : columns.index("seed")]
    except ValueError:
        raise ConfigError("expected a sweep table with repeat and seed columns") from None


def _value(text: str):
    try:
        return float(text)
    except ValueError:
        return text


def draw_sweep_summary(
    sweep_dir: str | Path,
    out_png: str | Path | None = None,
    *,
    metric: str = "freeze_ratio",
    x: str | None = None,
) -> Path:
    """Draw `sweep_dir/summary-<metric>.png` (or `out_png`) atomically; returns its path."""
    import csv
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from uma.atomic import atomic_write_bytes

    folder = Path(sweep_dir)
    table = folder / "sweep.csv"
    if not table.is_file():
        raise ConfigError(f"{table}: missing; expected the table `uma sweep` writes")
    with open(table, newline="", encoding="utf-8") as handle:
        reader = csv.DictReader(handle)
        rows = list(reader)
        columns = list(reader.fieldnames or [])
    keys = grid_keys_of(columns)
    if metric not in columns:
        raise ConfigError(f"--metric: {table} has no column {metric!r}")
    x = x or keys[0]
    if x not in keys:
        raise ConfigError(f"--x: expected one of the grid's keys {', '.join(keys)}, got {x!r}")
    others = [k for k in keys if k != x]
    ok = [r for r in rows if r["status"] == "ok" and r[metric] != ""]
    series: dict[tuple, dict] = defaultdict(lambda: defaultdict(list))
    for row in ok:
        series[tuple(row[k] for k in others)][_value(row[x])].append(float(row[metric]))

    fig = Figure(figsize=(7.5, 4.8), dpi=100, layout="constrained")
    ax = fig.subplots()
    xs_all = sorted({_value(r[x]) for r in rows}, key=lambda v: (isinstance(v, str), v))
    categorical = any(isinstance(v, str) for v in xs_all)
    for label_values, points in sorted(series.items()):
        xs = [v for v in xs_all if v in points]
        pos = [xs_all.index(v) for v in xs] if categorical else xs
        mean = [float(np.mean(points[v])) for v in xs]
        label = ", ".join(f"{k}={v}" for k, v in zip(others, label_values, strict=True)) or metric
        (line,) = ax.plot(pos, mean, marker="o", label=label)
        low = [min(points[v]) for v in xs]
        high = [max(points[v]) for v in xs]
        if any(h > lo for h, lo in zip(high, low, strict=True)):
            ax.fill_between(pos, low, high, color=line.get_color(), alpha=0.15, lw=0)
    if categorical:
        ax.set_xticks(range(len(xs_all)), [str(v) for v in xs_all])
    ax.set_xlabel(x)
    ax.set_ylabel(metric)
    failed = len(rows) - len(ok)
    repeats = max((int(r["repeat"]) for r in rows), default=0) + 1
    ax.set_title(
        f"{folder.name}: {metric} by {x} ({len(rows)} runs, mean of {repeats} seed(s), band: "
        f"range{f'; {failed} failed' if failed else ''})",
        fontsize=9,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    FigureCanvasAgg(fig)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    out = Path(out_png) if out_png is not None else folder / f"summary-{metric}.png"
    atomic_write_bytes(out, buffer.getvalue())
    return out
