"""`uma bench playout`: playout settings replayed exactly on a scenario's recorded runs.

Units: delays in ms, frozen shares as fractions of the display instants.

Each seed is run once, in full, with the scenario's own playout (one task for the sweep
executor, `uma.experiments`, so `--workers` spreads them); the run's decoded frames are its
playout recording (`uma.sim.playout_replay`). Each setting (`receiver.adaptive` keys over the
scenario's own, with the adaptive playout) is then replayed on every seed's recording, which
gives exactly the display a full run with that setting gives, in a fraction of a second. Per
setting and seed: `delay_p95_ms`, `delay_median_ms`, `freeze_ratio` and `by_technology` frozen
shares as `metrics.json` counts them; per setting the paired-median change against the
scenario's own playout over the seeds. `exact` says, per seed, whether the replay of the run's
own playout reproduced its display instants, shown frames and frozen flags.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from uma.config.scenario import AdaptivePlayoutConfig, ReceiverConfig, Scenario

__all__ = [
    "PlayoutBenchConfig",
    "METRIC_KEYS",
    "adaptive_keys",
    "grid_settings",
    "setting_receiver",
    "record_task",
    "display_metrics",
    "run_playout_bench",
    "format_table",
]

METRIC_KEYS = ("delay_p95_ms", "delay_median_ms", "freeze_ratio")


@dataclass(frozen=True)
class PlayoutBenchConfig:
    """The scenario, its seeds, and the settings to replay: each a mapping of
    `receiver.adaptive` keys to values over the scenario's own."""

    scenario: Scenario
    seeds: tuple[int, ...]
    settings: tuple[dict[str, Any], ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        if not self.seeds:
            raise ValueError("seeds: expected at least one seed")
        for setting in self.settings:
            setting_receiver(self.scenario.receiver, setting)  # ValueError names a bad one


def adaptive_keys() -> tuple[str, ...]:
    """The keys a setting may set: `receiver.adaptive`'s."""
    return tuple(AdaptivePlayoutConfig.model_fields)


def setting_receiver(own: ReceiverConfig, setting: dict[str, Any]) -> ReceiverConfig:
    """The receiver of `setting`: the adaptive playout, `setting`'s keys over `own`'s adaptive
    settings (the empty setting is `own` itself); a bad key or value is a ValueError naming it."""
    if not setting:
        return own
    unknown = sorted(set(setting) - set(adaptive_keys()))
    if unknown:
        raise ValueError(f"{unknown[0]}: unknown receiver.adaptive key")
    from pydantic import ValidationError

    try:
        adaptive = AdaptivePlayoutConfig.model_validate(own.adaptive.model_dump() | setting)
    except ValidationError as err:
        first = err.errors()[0]
        where = ".".join(str(part) for part in first["loc"]) or label(setting)
        message = first["msg"].removeprefix("Value error, ")
        found = first.get("input")
        got = "" if isinstance(found, dict) else f", got {found!r}"
        raise ValueError(f"{where}: {message}{got}") from None
    return own.model_copy(update={"playout": "adaptive", "adaptive": adaptive})


def grid_settings(grid: dict[str, Any], fixed: dict[str, Any] | None = None) -> list[dict]:
    """Every combination of the grid's values (a key's value or list of values), each with
    the `fixed` keys too."""
    keys = list(grid)
    values = [v if isinstance(v, list) else [v] for v in grid.values()]
    return [
        (fixed or {}) | dict(zip(keys, combo, strict=True)) for combo in itertools.product(*values)
    ]


def label(setting: dict[str, Any]) -> str:
    """A setting's name: its keys and values, or `own`."""
    return " ".join(f"{key}={value}" for key, value in setting.items()) or "own"


def record_task(task: dict[str, Any]) -> dict[str, Any]:
    """One seed's full run with the scenario's own playout: its recording, its metrics'
    figures, and whether the replay of its own playout reproduces it (an executor task)."""
    from uma.sim import run_scenario
    from uma.sim.playout_replay import recording_of, replay
    from uma.sim.summary import run_metrics

    start = time.perf_counter()
    scenario = Scenario.model_validate(task["scenario"])
    result = run_scenario(scenario)
    recording = recording_of(result)
    own = replay(recording)
    log = result.log
    exact = all(
        np.array_equal(getattr(own, key), log[key])
        for key in ("display_ms", "shown_frame", "frozen")
    )
    metrics = run_metrics(result)
    return {
        "seed": scenario.seed,
        "recording": recording,
        "exact": exact,
        "run": {key: metrics[key] for key in METRIC_KEYS},
        "wall_s": round(time.perf_counter() - start, 1),
    }


def _stat(values: np.ndarray, fn) -> float | None:
    """As `metrics.json` rounds an aggregate (`uma.metrics.aggregate`)."""
    values = values[np.isfinite(values)]
    return round(float(fn(values)), 4) if values.size else None


def display_metrics(recording, shown) -> dict[str, Any]:
    """The delay and freeze figures of a replayed display (`uma.sim.playout_replay.Replay`),
    as `metrics.json` counts them."""
    from uma.metrics.delay import display_delays_ms

    delays = display_delays_ms(recording.capture_ms, shown.display_ms, shown.shown_frame)
    frozen = np.asarray(shown.frozen)
    technologies = np.array(
        [
            "" if not np.isfinite(t_ms) else recording.technology_at(t_ms / 1000.0)
            for t_ms in shown.display_ms.tolist()
        ],
        dtype=object,
    ).astype(str)
    return {
        "delay_p95_ms": _stat(delays, lambda v: np.percentile(v, 95)),
        "delay_median_ms": _stat(delays, np.median),
        "freeze_ratio": round(float(frozen.mean()), 4) if frozen.size else None,
        "by_technology": {
            tech: round(float(frozen[technologies == tech].mean()), 4)
            for tech in sorted(set(technologies.tolist()) - {""})
        },
    }


def _paired_change(rows: dict[int, dict], own: dict[int, dict]) -> dict[str, Any]:
    """Per figure, the median over the seeds of the setting's value minus the own playout's."""

    def median(pairs: list[tuple[Any, Any]]) -> float | None:
        diffs = [a - b for a, b in pairs if a is not None and b is not None]
        return round(float(np.median(diffs)), 4) if diffs else None

    out: dict[str, Any] = {
        key: median([(rows[s][key], own[s][key]) for s in rows]) for key in METRIC_KEYS
    }
    techs = sorted({t for row in rows.values() for t in row["by_technology"]})
    out["by_technology"] = {
        tech: median(
            [(rows[s]["by_technology"].get(tech), own[s]["by_technology"].get(tech)) for s in rows]
        )
        for tech in techs
    }
    return out


def _records(
    config: PlayoutBenchConfig, executor, progress: Callable[[str], None] | None
) -> dict[int, dict]:
    """Each seed's recording run, by seed."""
    base = config.scenario.model_dump(mode="json")
    tasks = [base | {"seed": seed} for seed in config.seeds]
    tasks = [{"scenario": data} for data in tasks]
    replies: Iterator[dict[str, Any]] = (
        executor.map_unordered(record_task, tasks)
        if executor is not None
        else map(record_task, tasks)
    )
    records: dict[int, dict] = {}
    for reply in replies:
        records[reply["seed"]] = reply
        if progress is not None:
            progress(f"seed {reply['seed']}: recorded in {reply['wall_s']} s")
    return records


def run_playout_bench(
    config: PlayoutBenchConfig,
    *,
    executor=None,
    progress: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Record every seed, replay every setting on each; the JSON object of docs/benchmarks.md."""
    from uma.sim.playout_replay import replay

    records = _records(config, executor, progress)
    own_receiver = config.scenario.receiver
    settings = [{}] + [dict(s) for s in config.settings if s]
    rows_by_setting = []
    for setting in settings:
        receiver = setting_receiver(own_receiver, setting)
        start = time.perf_counter()
        rows = {
            seed: display_metrics(records[seed]["recording"], replay(
                records[seed]["recording"], receiver=receiver
            ))
            for seed in config.seeds
        }  # fmt: skip
        rows_by_setting.append((setting, rows, time.perf_counter() - start))
    own_rows = rows_by_setting[0][1]
    return {
        "scenario": config.scenario.name,
        "seeds": list(config.seeds),
        "playout": own_receiver.playout,
        "adaptive": own_receiver.adaptive.model_dump(mode="json"),
        "runs": {
            str(seed): {"exact": records[seed]["exact"], "wall_s": records[seed]["wall_s"]}
            | records[seed]["run"]
            for seed in config.seeds
        },
        "settings": [
            {
                "label": label(setting),
                "set": setting,
                "replay_s": round(wall_s, 3),
                "seeds": {str(seed): row for seed, row in rows.items()},
                "change": _paired_change(rows, own_rows),
            }
            for setting, rows, wall_s in rows_by_setting
        ],
    }


def format_table(result: dict[str, Any]) -> str:
    """One line a setting: median p95, median and frozen share over the seeds, and the
    paired-median changes against the scenario's own playout."""
    exact = all(run["exact"] for run in result["runs"].values())
    lines = [
        f"{result['scenario']}, seeds {','.join(map(str, result['seeds']))}; replay of the own "
        f"playout {'exact' if exact else 'NOT EXACT'} on every seed",
        f"{'setting':<44} {'p95 ms':>9} {'median ms':>10} {'frozen':>7} "
        f"{'d p95':>8} {'d median':>9} {'d frozen':>9}",
    ]
    for entry in result["settings"]:
        median = _median_of(list(entry["seeds"].values()))
        change = entry["change"]
        lines.append(
            f"{entry['label'][:44]:<44} {median('delay_p95_ms'):>9.0f} "
            f"{median('delay_median_ms'):>10.0f} {median('freeze_ratio'):>7.4f} "
            f"{_signed(change['delay_p95_ms'], 0):>8} {_signed(change['delay_median_ms'], 0):>9} "
            f"{_signed(change['freeze_ratio'], 4):>9}"
        )
    return "\n".join(lines)


def _median_of(rows: list[dict[str, Any]]) -> Callable[[str], float]:
    """The median over `rows` of a figure (NaN when no row has it)."""

    def median(key: str) -> float:
        values = [row[key] for row in rows if row[key] is not None]
        return float(np.median(values)) if values else float("nan")

    return median


def _signed(value: float | None, digits: int) -> str:
    return "n/a" if value is None else f"{value:+.{digits}f}"
