"""`uma bench headline`: what switching to the model-based codec buys, on two commutes.

Units: rates in kbit/s, delays in ms, PSNR in dB, times in seconds, MDE in pixels.

Each scenario runs with six engines on the same source and route (same seed):
- `h264`: the H.264 ladder only (`engine.switching.policy: none`);
- `uma`: switching between H.264 and MBC with the scenario's switching policy (the threshold
  policy when the scenario names none): it knows only what the engine measures;
- `predictive`: the predictive policy, which also reads the route's coverage map (the
  scenario's technology segments) and switches `lookahead_ms` before a GPRS or GSM segment
  (beyond the required engines: an extra row);
- `oracle`: an upper bound that knows the trace: the oracle rate policy (the true capacity)
  and the oracle switching policy (the lowest true capacity over the look-ahead window);
- `av1`: the AV1 ladder only (`engine.codec: av1`, SVT-AV1 at a real-time preset), and
  `av1+mbc`: AV1 with the threshold switching policy, so the table says whether switching to
  the model-based codec still pays against a modern codec at low rates.
All play out adaptively (`receiver.playout: adaptive`, unless `playout` says otherwise):
with a fixed 300 ms deadline GSM's 250 ms one-way delay alone would freeze every engine there,
whatever it sends. `init_mde_px` is the median mean distance error of the MBC initialisations
against the source's ground truth (the talking head has it; real video has none: null).
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from uma.codecs import full_frame_names, model_names
from uma.config.scenario import Scenario
from uma.experiments.uplink_store import StoreSettings

__all__ = [
    "HeadlineConfig",
    "ENGINES",
    "engine_scenario",
    "pair_task",
    "run_pair",
    "run_headline",
    "format_table",
]

# The engines, named after the registry's codecs (the JSON keys docs/benchmarks.md fixes:
# `h264`, `av1`, `av1+mbc`): the first full-frame codec alone, the newest (the registry's last
# full-frame codec) alone and with the model codec.
BASE, NEWEST = full_frame_names()[0], full_frame_names()[-1]
WITH_MODEL = f"{NEWEST}+{model_names()[0]}"
ENGINES = (BASE, "uma", "predictive", "oracle", NEWEST, WITH_MODEL)


@dataclass(frozen=True)
class _Engine:
    """What an engine changes in a scenario: `codec`, the full-frame codec it runs on its own
    ladder (None: the scenario's); `switching`, its switching policy (`scenario`: the
    scenario's own, the threshold policy when that is `none` or `oracle`); `oracle` also makes
    the rate policy the oracle."""

    codec: str | None
    switching: str


_ENGINE_SETTINGS = {
    BASE: _Engine(BASE, "none"),
    "uma": _Engine(None, "scenario"),
    "predictive": _Engine(None, "predictive"),
    "oracle": _Engine(None, "oracle"),
    NEWEST: _Engine(NEWEST, "none"),
    WITH_MODEL: _Engine(NEWEST, "scenario"),
}
ROW_KEYS = (
    "freeze_ratio",
    "displayed_fps",
    "psnr_db",
    "ssim",
    "psnr_face_db",
    "ssim_face",
    "delay_p95_ms",
    "kbps_h264",
    "kbps_mbc",
)
LOW_TECHNOLOGIES = ("GPRS", "GSM")


@dataclass(frozen=True)
class HeadlineConfig:
    scenarios: tuple[Scenario, ...]
    playout: str = "adaptive"  # every engine's receiver playout ("fixed" keeps the scenario's)
    out_dir: Path | None = None  # each run's results folder under it, when given
    # the store of sender streams the pairs share (`uma.experiments.uplink_store`; None: each
    # pair computes its stream; the rows are the same)
    uplink: StoreSettings | None = None


def engine_scenario(scenario: Scenario, engine: str, *, playout: str = "adaptive") -> Scenario:
    """`scenario` as engine `engine` (one of `ENGINES`) runs it."""
    if engine not in ENGINES:
        raise ValueError(f"engine: expected one of {', '.join(ENGINES)}, got {engine!r}")
    settings = _ENGINE_SETTINGS[engine]
    config = scenario.engine
    switching = config.switching
    if settings.codec is not None and (settings.codec != config.codec or engine != BASE):
        # the codec's own ladder (codecs/<codec>.yaml), whatever the scenario named for another
        config = config.model_copy(update={"codec": settings.codec, "ladder": None})
    policy = settings.switching
    if policy == "scenario":
        policy = switching.policy if switching.policy not in ("none", "oracle") else "threshold"
    config = config.model_copy(
        update={"switching": switching.model_copy(update={"policy": policy})}
    )
    if policy == "oracle":
        config = config.model_copy(update={"policy": "oracle"})
    receiver = scenario.receiver
    if playout == "adaptive":
        receiver = receiver.model_copy(update={"playout": "adaptive"})
    return scenario.model_copy(update={"engine": config, "receiver": receiver})


@functools.lru_cache(maxsize=4)
def _truth_source(source_json: str, seed: int):
    """The source a run read, reopened once per process for its ground truth (engines share it)."""
    from uma.config.scenario import SourceConfig
    from uma.sim.sources import open_source

    return open_source(SourceConfig.model_validate_json(source_json), seed=seed)


def init_mde_px(result) -> float | None:
    """Median MDE of the run's MBC initialisations against the source's ground truth."""
    from uma.fit.mde import mde_px

    if not result.model.inits or result.description.content is None:
        return None
    source = _truth_source(result.scenario.source.model_dump_json(), result.scenario.seed)
    truth = getattr(source, "ground_truth", None)
    if truth is None:
        return None
    model = result.description.content.model
    errors = [
        mde_px(model, params, truth(frame)["params"])
        for frame, params in result.model.inits
        if params is not None
    ]
    return round(float(np.median(errors)), 3) if errors else None


def switch_lag_s(result) -> float | None:
    """Mean seconds from each handover into GPRS or GSM to the first model-codec frame sent.

    Only handovers from another technology count (GPRS to GSM continues a stretch already
    timed). A handover while the last frame sent was a model-codec frame counts 0; one after
    which no model-codec frame is sent before the route leaves GPRS and GSM is left out. None
    when no handover into them was followed by a model-codec frame.
    """
    from uma.codecs import model_names

    log = result.log
    capture_s = np.asarray(log["capture_ms"], dtype=float) / 1000.0
    sent = np.asarray(log["sent"]).astype(bool)
    on_model = np.isin(np.asarray(log["codec"]).astype(str), list(model_names()))
    handovers = []
    for event in result.events:
        old, _, new = event.detail.partition("->")
        if event.kind == "handover":
            handovers.append((event.time_s, old.strip(), new.strip()))
    lags = []
    for k, (time_s, old, new) in enumerate(handovers):
        if new not in LOW_TECHNOLOGIES or old in LOW_TECHNOLOGIES:
            continue  # GPRS -> GSM continues a stretch already timed
        # the stretch ends at the next handover out of GPRS and GSM (frames' own technology
        # labels are unreliable within the handover gap)
        ends = [t for t, _, n in handovers[k + 1 :] if n not in LOW_TECHNOLOGIES]
        end_s = ends[0] if ends else np.inf
        after = capture_s >= time_s
        earlier = np.flatnonzero(~after & sent)
        if earlier.size and on_model[earlier[-1]]:
            lags.append(0.0)
            continue
        first = np.flatnonzero(after & (capture_s < end_s) & sent & on_model)
        if first.size:
            lags.append(float(capture_s[first[0]] - time_s))
    return round(float(np.mean(lags)), 3) if lags else None


def _row(result, metrics: dict[str, Any]) -> dict[str, Any]:
    row: dict[str, Any] = {key: metrics.get(key) for key in ROW_KEYS}
    from uma.codecs import metric_key

    # the full-frame ladder's rate, whichever codec it is (kbps_h264 stays H.264's own)
    row["kbps_video"] = metrics.get(f"kbps_{metric_key(result.scenario.engine.codec)}")
    # the model-aided refresh's own rate (None when the engine does not refresh)
    row["kbps_refresh"] = metrics.get("kbps_refresh")
    row["codec"] = result.scenario.engine.codec
    row["switch_lag_s"] = switch_lag_s(result)
    row["switches"] = metrics["codec_switches"]
    row["inits"] = metrics["inits"]
    row["init_mde_px"] = init_mde_px(result)
    row["description_delivered_s"] = metrics["description_delivered_s"]
    row["by_technology"] = metrics["by_technology"]
    # Not among the required keys, but a reader of the table needs them.
    row["rung_switches"] = metrics["switches"]
    row["init_failures"] = metrics["init_failures"]
    row["mbc_refused_reason"] = metrics["mbc_refused_reason"]
    return row


def _targets(rows: dict[str, dict[str, Any]], *, real: bool) -> dict[str, Any]:
    base, uma = rows[BASE], rows["uma"]

    def low(row: dict[str, Any]) -> float | None:
        # Face SSIM over the GPRS and GSM display instants, weighted as the frames are.
        values = [
            row["by_technology"][t]["ssim_face"]
            for t in LOW_TECHNOLOGIES
            if t in row["by_technology"] and row["by_technology"][t]["ssim_face"] is not None
        ]
        return float(np.mean(values)) if values else None

    def compare(a: float | None, b: float | None, better) -> bool | None:
        return None if a is None or b is None else bool(better(a, b))

    if real:
        return {
            "freeze_ratio_lower": compare(
                uma["freeze_ratio"], base["freeze_ratio"], lambda a, b: a < b
            ),
            "psnr_face_db_at_least_h264": compare(
                uma["psnr_face_db"], base["psnr_face_db"], lambda a, b: a >= b
            ),
        }
    share = compare(uma["freeze_ratio"], base["freeze_ratio"], lambda a, b: b > 0)
    share = uma["freeze_ratio"] / base["freeze_ratio"] if share else None
    low_uma, low_base = low(uma), low(base)
    return {
        "freeze_ratio_share_of_h264": None if share is None else round(share, 3),
        "freeze_ratio_at_most_20_percent": None if share is None else share <= 0.2,
        "low_ssim_face_uma": None if low_uma is None else round(low_uma, 4),
        "low_ssim_face_h264": None if low_base is None else round(low_base, 4),
        "low_ssim_face_above_h264": compare(low_uma, low_base, lambda a, b: a > b),
    }


def pair_task(
    scenario: Scenario, engine: str, config: HeadlineConfig, *, inline_metrics: bool = False
) -> dict[str, Any]:
    """The task for `run_pair`: plain data that pickles small and travels to any worker.

    `inline_metrics` scores on the simulating thread (`metrics.workers: 0`), as a sweep's
    points do when the parallelism is across runs; the scores do not depend on it.
    """
    variant = engine_scenario(scenario, engine, playout=config.playout)
    out_dir = None if config.out_dir is None else config.out_dir / scenario.name / engine
    data = variant.model_dump(mode="json")
    if inline_metrics:
        data["metrics"] = dict(data.get("metrics", {}), workers=0)
    return {
        "scenario_name": scenario.name,
        "engine": engine,
        "scenario": data,
        "out_dir": None if out_dir is None else str(out_dir),
        "uplink": None if config.uplink is None else config.uplink.task(),
    }


def run_pair(task: dict[str, Any]) -> dict[str, Any]:
    """Simulate one scenario-engine pair (in whatever process runs it); its table row."""
    from uma.config.scenario import Scenario
    from uma.experiments.uplink_store import open_store
    from uma.sim import run_scenario
    from uma.sim.summary import run_metrics, save_run

    start = time.perf_counter()
    store = open_store(task.get("uplink"))
    result = run_scenario(Scenario.model_validate(task["scenario"]), uplink=store)
    if task["out_dir"] is not None:
        metrics = save_run(result, Path(task["out_dir"]))
    else:
        metrics = run_metrics(result)
    row = _row(result, metrics)
    row["wall_s"] = round(time.perf_counter() - start, 1)
    return {"scenario_name": task["scenario_name"], "engine": task["engine"], "row": row}


def run_headline(config: HeadlineConfig, *, progress=None, executor=None) -> dict[str, Any]:
    """Every scenario with every engine; the JSON object of docs/benchmarks.md.

    Pairs run one after another in this process, or on `executor` (`uma.experiments`'s
    `make_executor`: local processes or a Dask cluster) in parallel; the rows are the same
    either way, only `wall_s` differs.
    """
    parallel = executor is not None
    tasks = [
        pair_task(s, engine, config, inline_metrics=parallel)
        for s in config.scenarios
        for engine in ENGINES
    ]
    replies = (
        executor.map_unordered(run_pair, tasks) if executor is not None else map(run_pair, tasks)
    )
    rows: dict[tuple[str, str], dict[str, Any]] = {}
    for reply in replies:
        rows[reply["scenario_name"], reply["engine"]] = reply["row"]
        if progress is not None:
            progress(f"{reply['scenario_name']} {reply['engine']}: {reply['row']['wall_s']} s")
    out: dict[str, Any] = {"playout": config.playout, "scenarios": {}, "targets": {}}
    for scenario in config.scenarios:
        by_engine = {engine: rows[scenario.name, engine] for engine in ENGINES}
        out["scenarios"][scenario.name] = by_engine
        real = scenario.source.kind != "talking-head"
        out["targets"][scenario.name] = _targets(by_engine, real=real)
    return out


def _fmt(value: Any, spec: str) -> str:
    return f"{'n/a':>{len(format(0, spec))}}" if value is None else format(value, spec)


def _ladders(result: dict[str, Any]) -> str:
    """Which full-frame codec each engine ran, by the rows' own `codec` (registry labels)."""
    from uma.codecs import spec

    engines: dict[str, list[str]] = {}
    for rows in result["scenarios"].values():
        for engine, row in rows.items():
            names = engines.setdefault(spec(row["codec"]).label, [])
            if engine not in names:
                names.append(engine)
    return "; ".join(f"{label} in {', '.join(names)}" for label, names in engines.items())


def format_table(result: dict[str, Any]) -> str:
    """The readable table: one block per scenario, one line per engine."""
    lines = [f"uma bench headline (every engine plays out {result['playout']})"]
    head = (
        f"  {'engine':<8}{'frozen':>7}{'fps':>6}{'PSNR':>6}{'SSIM':>7}{'face dB':>8}"
        f"{'face SSIM':>10}{'p95 ms':>8}{'video':>7}{'MBC':>6}{'refr':>6}{'sw':>4}{'init':>5}"
        f"{'MDE':>6}{'descr s':>8}{'lag s':>6}"
    )
    for name, rows in result["scenarios"].items():
        lines += ["", f"{name}", head]
        for engine, row in rows.items():
            lines.append(
                f"  {engine:<8}{_fmt(row['freeze_ratio'], '7.3f')}"
                f"{_fmt(row['displayed_fps'], '6.1f')}{_fmt(row['psnr_db'], '6.1f')}"
                f"{_fmt(row['ssim'], '7.3f')}{_fmt(row['psnr_face_db'], '8.1f')}"
                f"{_fmt(row['ssim_face'], '10.3f')}{_fmt(row['delay_p95_ms'], '8.0f')}"
                f"{_fmt(row['kbps_video'], '7.1f')}{_fmt(row['kbps_mbc'], '6.2f')}"
                f"{_fmt(row.get('kbps_refresh'), '6.2f')}"
                f"{row['switches']:>4}{row['inits']:>5}{_fmt(row['init_mde_px'], '6.2f')}"
                f"{_fmt(row['description_delivered_s'], '8.1f')}"
                f"{_fmt(row['switch_lag_s'], '6.1f')}"
            )
        techs = sorted({t for row in rows.values() for t in row["by_technology"]})
        lines.append("  frozen / face SSIM by technology:")
        for engine, row in rows.items():
            cells = []
            for tech in techs:
                cell = row["by_technology"].get(tech)
                if cell is not None:
                    cells.append(
                        f"{tech} {_fmt(cell['freeze_ratio'], '.2f')}/"
                        f"{_fmt(cell['ssim_face'], '.3f')}"
                    )
            lines.append(f"    {engine:<8}" + "  ".join(cells))
        targets = result["targets"].get(name, {})
        lines.append("  targets: " + ", ".join(f"{k} {v}" for k, v in targets.items()))
    lines.append(
        "\nfrozen: share of display instants frozen; fps: displayed frames/s; face: the "
        f"source's face box; video: kbit/s of the full-frame ladder ({_ladders(result)}); "
        "lag s: from a handover into GPRS/GSM to the first model-codec frame; sw: codec "
        "switches; init: model-codec initialisations; MDE: their median error against ground "
        "truth (px); descr s: when the content description arrived."
    )
    return "\n".join(lines)
