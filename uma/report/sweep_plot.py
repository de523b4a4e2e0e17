"""A sweep's summary plot: one metric against one grid key, a line per combination of the others.

Units: those of the metric's and the key's names. Repeats (seeds) of a point are averaged and
their range drawn as a band; failed points and points not run yet (`missing`) are left out and
counted in the title. The table is read by `uma.experiments.table.read_sweep_table`: a damaged
`sweep.csv` is one `ConfigError` naming its line.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uma.errors import ConfigError

__all__ = ["draw_sweep_summary", "grid_keys_of", "sweep_series", "SweepSeries"]


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


@dataclass(frozen=True)
class SweepSeries:
    """What the plot draws: per combination of the other keys, x value -> the metric's values."""

    metric: str
    x: str
    others: tuple[str, ...]
    xs: tuple  # every x value of the table, numbers first
    series: dict[tuple, dict]
    runs: int
    failed: int
    missing: int
    repeats: int


def sweep_series(sweep_dir: str | Path, *, metric: str, x: str | None) -> SweepSeries:
    """Read `sweep_dir/sweep.csv` and gather `metric` by `x`; `ConfigError` for bad input."""
    from uma.report.sweep_table import read_sweep_table

    table_path = Path(sweep_dir) / "sweep.csv"
    if not table_path.is_file():
        raise ConfigError(f"{table_path}: missing; expected the table `uma sweep` writes")
    table = read_sweep_table(table_path)
    keys = list(table.grid_keys)
    if metric not in table.columns:
        raise ConfigError(f"--metric: {table_path} has no column {metric!r}")
    if not keys:
        raise ConfigError(f"{table_path}:1: expected grid keys between repeat and seed, got none")
    x = x or keys[0]
    if x not in keys:
        raise ConfigError(f"--x: expected one of the grid's keys {', '.join(keys)}, got {x!r}")
    others = tuple(k for k in keys if k != x)
    series: dict[tuple, dict] = defaultdict(lambda: defaultdict(list))
    for index, row in enumerate(table.rows):
        value = table.number(index, metric) if row["status"] == "ok" else None
        if value is not None:
            series[tuple(row[k] for k in others)][_value(row[x])].append(value)
    xs = sorted({_value(r[x]) for r in table.rows}, key=lambda v: (isinstance(v, str), v))
    used = sum(len(v) for points in series.values() for v in points.values())
    missing = sum(r["status"] == "missing" for r in table.rows)
    return SweepSeries(
        metric,
        x,
        others,
        tuple(xs),
        {k: dict(v) for k, v in series.items()},
        runs=len(table.rows),
        failed=len(table.rows) - used - missing,
        missing=missing,
        repeats=max((int(r["repeat"]) for r in table.rows), default=0) + 1,
    )


def draw_sweep_summary(
    sweep_dir: str | Path,
    out_png: str | Path | None = None,
    *,
    metric: str = "freeze_ratio",
    x: str | None = None,
) -> Path:
    """Draw `sweep_dir/summary-<metric>.png` (or `out_png`) atomically; returns its path."""
    import io

    folder = Path(sweep_dir)
    data = sweep_series(folder, metric=metric, x=x)  # bad input fails before matplotlib loads

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from uma.atomic import atomic_write_bytes

    fig = Figure(figsize=(7.5, 4.8), dpi=100, layout="constrained")
    ax = fig.subplots()
    xs_all = list(data.xs)
    categorical = any(isinstance(v, str) for v in xs_all)
    for label_values, points in sorted(data.series.items()):
        xs = [v for v in xs_all if v in points]
        pos = [xs_all.index(v) for v in xs] if categorical else xs
        mean = [float(np.mean(points[v])) for v in xs]
        label = (
            ", ".join(f"{k}={v}" for k, v in zip(data.others, label_values, strict=True)) or metric
        )
        (line,) = ax.plot(pos, mean, marker="o", label=label)
        low = [min(points[v]) for v in xs]
        high = [max(points[v]) for v in xs]
        if any(h > lo for h, lo in zip(high, low, strict=True)):
            ax.fill_between(pos, low, high, color=line.get_color(), alpha=0.15, lw=0)
    if categorical:
        ax.set_xticks(range(len(xs_all)), [str(v) for v in xs_all])
    ax.set_xlabel(data.x)
    ax.set_ylabel(metric)
    notes = ""
    if data.failed:
        notes += f"; {data.failed} failed"
    if data.missing:
        notes += f"; {data.missing} not run: sweep incomplete"
    ax.set_title(
        f"{folder.name}: {metric} by {data.x} ({data.runs} runs, mean of {data.repeats} seed(s), "
        f"band: range{notes})",
        fontsize=9,
    )
    ax.grid(alpha=0.3)
    if data.series:
        ax.legend(fontsize=8)
    FigureCanvasAgg(fig)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    out = Path(out_png) if out_png is not None else folder / f"summary-{metric}.png"
    atomic_write_bytes(out, buffer.getvalue())
    return out
