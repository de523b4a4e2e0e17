"""`uma bench links`: the Salsify setting through the whole simulation on many measured traces.

Units: delays in ms, rates in kbit/s, SSIM in dB, utilisation and shares as fractions.

Each trace replaces the trace of the Salsify scenario (`scenarios/salsify-tmobile-umts.yaml`:
CIF talking head, 20 ms one way, drop-tail queue, adaptive playout) and runs for its first
`duration_s` seconds (shorter traces run whole) once per engine of `ENGINES`. An engine is data:
the scenario keys it sets (`uma`: the default controller; `gcc`: the GCC baseline; `webrtc`:
aiortc's estimator; `oracle`: the oracle policy). Every (trace, engine) pair is one task for the sweep executor (`uma.experiments`), so
`--workers` and `--scheduler` spread them. `utilisation` is what the engine sent (every codec's
bits and padding) over what the trace could carry in the same time; `keyframe_bits_share` the
share of the sent bits that were keyframes; `bound` the least delay the trace's link allows any
engine (`uma.bench.bound`), for packets of the headers alone and of the scenario's full size.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from uma.config.scenario import MAX_DURATION_S, Scenario

__all__ = [
    "ENGINES",
    "ROW_KEYS",
    "DEFAULT_TRACE_DIRS",
    "LinksConfig",
    "default_traces",
    "link_task",
    "run_link",
    "run_links",
    "median_row",
    "link_bound",
]

# engine -> the scenario keys it sets (key path, value)
ENGINES: dict[str, tuple[tuple[str, Any], ...]] = {
    "uma": (("engine.estimator.kind", "uma"),),
    "gcc": (("engine.estimator.kind", "gcc"),),
    "webrtc": (("engine.estimator.kind", "webrtc"),),
    "oracle": (("engine.policy", "oracle"),),
}
ROW_KEYS = (
    "delay_p95_ms",
    "delay_median_ms",
    "ssim_db",
    "ssim_db_unfrozen",
    "freeze_ratio",
    "kbps_video",
    "utilisation",
    "keyframe_bits_share",
)
# folder under the shared data's traces -> the file-name patterns of its downlink traces
DEFAULT_TRACE_DIRS: dict[str, tuple[str, ...]] = {
    "mahimahi": ("*.down",),
    "riiser-hsdpa-raw": ("*.log",),
    "nyu-mets": ("*.csv",),
    "pensieve-cooked": ("*.log", "norway_*", "trace_*"),
    "ucc-5g-raca2020": ("*.csv",),
    "mp-traces-wifi-cellular": ("*.csv",),
}


@dataclass(frozen=True)
class LinksConfig:
    scenario: Scenario  # the Salsify scenario: everything but the trace
    traces: tuple[str, ...]  # trace files, resolved
    duration_s: float = 300.0
    engines: tuple[str, ...] = tuple(ENGINES)
    published_file: str | None = None


def default_traces(traces_dir: Path) -> list[Path]:
    """The default set under `traces_dir`, in a fixed order (folder, then name)."""
    found: list[Path] = []
    for folder, patterns in DEFAULT_TRACE_DIRS.items():
        names = {p for pattern in patterns for p in (traces_dir / folder).glob(pattern)}
        found += sorted(p for p in names if p.is_file())
    return found


def trace_label(path: str) -> str:
    """A trace's name in the table: its file name without direction or compression suffixes."""
    from uma.bench.published import trace_name

    return trace_name(path)


def _set(data: dict[str, Any], key_path: str, value: Any) -> None:
    from uma.experiments.keypaths import parse_key_path, set_key_path

    set_key_path(data, parse_key_path(key_path), value)


def link_task(config: LinksConfig, trace: str, engine: str, trace_s: float) -> dict[str, Any]:
    """Plain data for `run_link`: the scenario on `trace` as `engine` runs it."""
    data = config.scenario.model_dump(mode="json")
    label = trace_label(trace)
    data["name"] = f"links-{label.lower()}"
    # The route holds the trace whole, up to what a segment may last (NYU-METS's BB62 rides
    # 22,005 s); the run covers its first `duration_s`.
    route_s = min(trace_s, MAX_DURATION_S)
    data["route"] = [dict(data["route"][0], trace=trace, duration_s=route_s)]
    data["duration_s"] = min(config.duration_s, route_s)
    data["metrics"] = dict(data.get("metrics", {}), workers=0)
    for key_path, value in ENGINES[engine]:
        _set(data, key_path, value)
    return {"trace": label, "engine": engine, "scenario": data}


def _check_task(task: dict[str, Any]) -> None:
    """`ConfigError` naming the trace when `task`'s scenario does not validate (a trace too
    short to hold one frame)."""
    from pydantic import ValidationError

    from uma.errors import ConfigError

    try:
        Scenario.model_validate(task["scenario"])
    except ValidationError as err:
        message = err.errors()[0]["msg"].removeprefix("Value error, ")
        trace = task["scenario"]["route"][0]["trace"]
        raise ConfigError(
            f"--trace {trace}: the links scenario cannot run on it: {message}"
        ) from None


def row_of(result, metrics: dict[str, Any]) -> dict[str, Any]:
    """One engine's row from a run: the `ROW_KEYS` plus the capacity it saw."""
    from uma.codecs import metric_key

    log = result.log
    sent = np.asarray(log["sent"]).astype(bool)
    size = np.asarray(log["size_bits"], dtype=float)
    key = np.asarray(log["keyframe"]).astype(bool)
    frame_bits = float(size[sent].sum())
    duration_s = metrics["duration_s"]
    sent_kbps = sum(metrics["bits_sent"].values()) / duration_s / 1000.0
    capacity = metrics["capacity_mean_kbps"]
    return {
        "delay_p95_ms": metrics["delay_p95_ms"],
        "delay_median_ms": metrics["delay_median_ms"],
        "ssim_db": metrics["ssim_db"],
        "ssim_db_unfrozen": metrics.get("ssim_db_unfrozen"),
        "freeze_ratio": metrics["freeze_ratio"],
        "kbps_video": metrics.get(f"kbps_{metric_key(result.scenario.engine.codec)}"),
        "utilisation": round(sent_kbps / capacity, 4) if capacity else None,
        "keyframe_bits_share": round(float(size[sent & key].sum()) / frame_bits, 4)
        if frame_bits
        else None,
        "capacity_kbps_mean": capacity,
    }


def run_link(task: dict[str, Any]) -> dict[str, Any]:
    """Simulate one (trace, engine) pair in whatever process runs it; its row."""
    from uma.sim import run_scenario
    from uma.sim.summary import run_metrics

    start = time.perf_counter()
    result = run_scenario(Scenario.model_validate(task["scenario"]))
    row = row_of(result, run_metrics(result))
    row["wall_s"] = round(time.perf_counter() - start, 1)
    return {"trace": task["trace"], "engine": task["engine"], "row": row}


def link_bound(task: dict[str, Any]) -> dict[str, Any]:
    """The least delay the task's link allows any engine (`uma bench bound`), keyed by packet
    size in bytes: the headers alone, and the scenario's full packet (`downlink.packet_bytes`)."""
    from uma.bench.bound import BoundConfig, scenario_bound
    from uma.sim.packets import HEADER_BYTES

    scenario = Scenario.model_validate(task["scenario"])
    sizes = (HEADER_BYTES, scenario.downlink.packet_bytes)
    row = scenario_bound(scenario, BoundConfig(scenarios=(scenario,), packet_bytes=sizes))
    return {
        size: {key: summary[key] for key in ("delay_p95_ms", "delay_median_ms")}
        for size, summary in row["packets"].items()
    }


def median_row(rows: Iterable[dict[str, Any]]) -> dict[str, Any]:
    """Per key, the median over the rows that have a value (None where none has)."""
    rows = list(rows)
    out: dict[str, Any] = {}
    for key in ROW_KEYS:
        values = [row[key] for row in rows if row.get(key) is not None]
        out[key] = round(float(np.median(values)), 4) if values else None
    return out


def run_links(
    config: LinksConfig,
    *,
    trace_durations_s: dict[str, float],
    executor=None,
    progress: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Every trace with every engine; the JSON object of docs/benchmarks.md."""
    from uma.bench.published import published_for

    tasks = [
        link_task(config, trace, engine, trace_durations_s[trace])
        for trace in config.traces
        for engine in config.engines
    ]
    for task in tasks:  # before any runs: a trace the scenario cannot run is one line
        _check_task(task)
    replies: Iterator[dict[str, Any]] = (
        executor.map_unordered(run_link, tasks) if executor is not None else map(run_link, tasks)
    )
    rows: dict[tuple[str, str], dict[str, Any]] = {}
    for reply in replies:
        rows[reply["trace"], reply["engine"]] = reply["row"]
        if progress is not None:
            progress(f"{reply['trace']} {reply['engine']}: {reply['row']['wall_s']} s")
    task_of = {task["trace"]: task for task in tasks}  # every engine's task has the same link
    traces: dict[str, Any] = {}
    for trace in config.traces:
        label = trace_label(trace)
        engines = {engine: rows[label, engine] for engine in config.engines}
        first = next(iter(engines.values()))
        traces[label] = {
            "file": trace,
            "duration_s": task_of[label]["scenario"]["duration_s"],  # what ran
            "capacity_kbps_mean": first["capacity_kbps_mean"],
            "bound": link_bound(task_of[label]),
            "engines": {
                engine: {key: row[key] for key in (*ROW_KEYS, "wall_s")}
                for engine, row in engines.items()
            },
            "published": published_for(trace, config.published_file),
        }
    median = {
        engine: median_row(t["engines"][engine] for t in traces.values())
        for engine in config.engines
    }
    return {
        "scenario": config.scenario.name,
        "duration_s": config.duration_s,
        "traces": traces,
        "median": median,
    }
