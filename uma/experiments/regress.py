"""The regression gate: compare each run's metrics with a baseline kept in the repository.

A suite file lists short scenarios, the baseline file and, per metric, the direction that is
worse and how far it may move that way:

```yaml
baseline: baseline.yaml            # relative to the suite file
machine_baselines: {avx512: baseline-avx512.yaml}   # optional: a machine class's own baseline
scenarios: [short-commute.yaml]    # scenario files; results are looked up by scenario name
metrics:
  kbps_h264:    {worse: up, relative: 0.05}    # bit rate may not rise more than 5 %
  psnr_db:      {worse: down, absolute: 0.3}   # PSNR may not fall more than 0.3 dB
  freeze_ratio: {worse: up, absolute: 0.02}
```

A metric is a key of `metrics.json`, or a dotted path into its nested objects
(`bits_sent.vp8`, `by_technology.GSM.freeze_ratio`). A tolerance with `only: [NAME, ...]` gates
those scenarios alone (a switching scenario's model-codec rate, a VP8 run's bits), so one suite
holds scenarios whose metrics differ.

The baseline is YAML, scenario name -> metric -> value (null where the metric has none), written
by `uma regress SUITE --update`. A metric the results lack, or null where the baseline has a
number, is a regression. Units are those of the metric's name.

A baseline belongs to a kind of machine as well as to the code (`uma.experiments.machine`):
`machine_baselines` maps a machine class to its own file; `baseline` serves every other class.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from uma.errors import ConfigError

__all__ = [
    "Tolerance",
    "Suite",
    "Check",
    "load_suite",
    "load_baseline",
    "compare",
    "format_checks",
    "metric_value",
    "has_metric",
    "check_only",
    "check_metric_paths",
]

_SUITE_KEYS = ("baseline", "machine_baselines", "scenarios", "metrics", "description")


@dataclass(frozen=True)
class Tolerance:
    """`worse` is "up" or "down"; the allowed move that way is `relative` (of |baseline|) or `absolute`."""

    worse: str
    relative: float | None = None
    absolute: float | None = None
    only: tuple[str, ...] | None = None  # scenario names it gates; None: every scenario

    def gates(self, scenario: str) -> bool:
        return self.only is None or scenario in self.only

    def allowed(self, baseline: float) -> float:
        if self.relative is not None:
            return self.relative * abs(baseline)
        return float(self.absolute)

    def describe(self) -> str:
        way = "rise" if self.worse == "up" else "fall"
        if self.relative is not None:
            return f"{way} <= {self.relative * 100:g} %"
        return f"{way} <= {self.absolute:g}"


@dataclass(frozen=True)
class Suite:
    path: Path
    baseline_path: Path  # the machine's own baseline if the suite has one, else `baseline`
    scenarios: tuple[Path, ...]
    metrics: dict[str, Tolerance]
    # metric -> `FILE:LINE (metrics.NAME)`, for the messages of checks made once runs are read
    where: dict[str, str] = field(default_factory=dict)
    machine: str = "default"  # the machine class the baseline was chosen for

    def metrics_of(self, scenario: str) -> dict[str, Tolerance]:
        """The metrics this suite gates for `scenario`."""
        return {name: tol for name, tol in self.metrics.items() if tol.gates(scenario)}


def metric_value(metrics: dict[str, Any] | None, name: str) -> Any:
    """`metrics[name]`, or the value at a dotted path (`by_technology.GSM.freeze_ratio`); None if absent."""
    if not metrics:
        return None
    if name in metrics:
        return metrics[name]
    value: Any = metrics
    for part in name.split("."):
        if not isinstance(value, dict) or part not in value:
            return None
        value = value[part]
    return value


@dataclass(frozen=True)
class Check:
    scenario: str
    metric: str
    baseline: float | None
    now: float | None
    change: str
    tolerance: str
    verdict: str  # ok, better, REGRESSED, missing

    @property
    def failed(self) -> bool:
        return self.verdict in ("REGRESSED", "missing")


def _number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _tolerance(spec: Any, where: str) -> Tolerance:
    """One metric's tolerance (`{worse, relative | absolute, only}`), checked; errors cite
    `where`."""
    if not isinstance(spec, dict) or set(spec) - {"worse", "relative", "absolute", "only"}:
        raise ConfigError(
            f"{where}: expected {{worse: up|down, relative: X or absolute: X"
            f"[, only: [scenario, ...]]}}, got {spec!r}"
        )
    only = spec.get("only")
    if only is not None and (
        not isinstance(only, list) or not only or not all(isinstance(n, str) for n in only)
    ):
        raise ConfigError(f"{where} only: expected a list of scenario names, got {only!r}")
    if spec.get("worse") not in ("up", "down"):
        raise ConfigError(f"{where} worse: expected up or down, got {spec.get('worse')!r}")
    given = [k for k in ("relative", "absolute") if k in spec]
    if len(given) != 1 or not _number(spec[given[0]]) or spec[given[0]] < 0:
        raise ConfigError(f"{where}: expected exactly one of relative or absolute, a number >= 0")
    return Tolerance(
        spec["worse"],
        spec.get("relative"),
        spec.get("absolute"),
        None if only is None else tuple(only),
    )


def load_suite(path: str | Path, machine: str = "default") -> Suite:
    """Parse a suite file; errors name its line and key. `machine` (a class of
    `uma.experiments.machine`) picks its own baseline when the suite keeps one."""
    from uma.config.yamlfile import load_yaml
    from uma.experiments.machine import machine_baselines

    path = Path(path)
    data, lines = load_yaml(path)
    if not isinstance(data, dict):
        raise ConfigError(
            f"{lines.where(())}: expected a mapping with baseline, scenarios, metrics"
        )
    for key in data:
        if key not in _SUITE_KEYS:
            raise ConfigError(
                f"{lines.where((key,))}: unknown key, expected one of {', '.join(_SUITE_KEYS)}"
            )
    folder = path.resolve().parent
    baseline = data.get("baseline")
    if not isinstance(baseline, str) or not baseline:
        raise ConfigError(f"{lines.where(('baseline',))}: expected the baseline file's path")
    by_machine = machine_baselines(
        data.get("machine_baselines"), lines.where(("machine_baselines",))
    )
    baseline = by_machine.get(machine, baseline)
    scenarios = data.get("scenarios")
    if (
        not isinstance(scenarios, list)
        or not scenarios
        or not all(isinstance(s, str) for s in scenarios)
    ):
        raise ConfigError(
            f"{lines.where(('scenarios',))}: expected a non-empty list of scenario files"
        )
    metrics = data.get("metrics")
    if not isinstance(metrics, dict) or not metrics:
        raise ConfigError(f"{lines.where(('metrics',))}: expected a mapping of metric -> tolerance")
    tolerances = {
        str(name): _tolerance(spec, lines.where(("metrics", name)))
        for name, spec in metrics.items()
    }
    return Suite(
        path=path,
        baseline_path=(folder / baseline).resolve(),
        scenarios=tuple((folder / s).resolve() for s in scenarios),
        metrics=tolerances,
        where={str(name): lines.where(("metrics", name)) for name in metrics},
        machine=machine,
    )


def check_only(suite: Suite, names: list[str]) -> None:
    """Raise `ConfigError` when a tolerance's `only:` names no scenario of the suite (by name,
    as its file's `name:` says), so no metric silently gates nothing."""
    for metric, tol in suite.metrics.items():
        for name in tol.only or ():
            if name not in names:
                hint = (
                    " (a scenario's name, not its file)" if name.endswith((".yaml", ".yml")) else ""
                )
                raise ConfigError(
                    f"{suite.where.get(metric, suite.path)} only: expected scenario names of "
                    f"this suite ({', '.join(names)}){hint}, got {name!r}"
                )


def has_metric(metrics: dict[str, Any] | None, name: str) -> bool:
    """Whether `metrics` holds `name` (a key, or a dotted path), null or not."""
    if not metrics:
        return False
    if name in metrics:
        return True
    value: Any = metrics
    for part in name.split("."):
        if not isinstance(value, dict) or part not in value:
            return False
        value = value[part]
    return True


def _paths(metrics: dict[str, Any], prefix: str = "") -> list[str]:
    out = []
    for key, value in metrics.items():
        out.append(prefix + str(key))
        if isinstance(value, dict):
            out += _paths(value, f"{prefix}{key}.")
    return out


def check_metric_paths(
    suite: Suite,
    now: dict[str, dict[str, Any] | None],
    *,
    baseline: dict[str, dict[str, Any]] | None = None,
    update: bool = False,
) -> None:
    """Raise `ConfigError` for a gated metric that no scenario's `metrics.json` holds (a typo
    would otherwise gate nothing, `null` in the baseline); with `update`, also for one that a
    scenario it gates lacks (writing `null` for it would gate nothing: narrow it with `only:`).

    A metric the `baseline` has a number for is no typo: when it vanishes from the results,
    that is a regression (`compare` says "missing"), not bad input. Scenarios without results
    (a failed run) are not looked at: the run's failure is reported.
    """
    import difflib

    read = {name: metrics for name, metrics in now.items() if metrics}
    for metric in suite.metrics:
        gated = [name for name in read if suite.metrics[metric].gates(name)]
        lacking = [name for name in gated if not has_metric(read[name], metric)]
        where = suite.where.get(metric, str(suite.path))
        known = not update and any(
            _number((baseline or {}).get(name, {}).get(metric)) for name in gated
        )
        if gated and len(lacking) == len(gated) and not known:
            known = sorted({p for name in gated for p in _paths(read[name])})
            close = difflib.get_close_matches(metric, known, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise ConfigError(
                f"{where}: no scenario's metrics.json has {metric!r} "
                f"(looked in {', '.join(gated)}){hint}"
            )
        if update and lacking:
            raise ConfigError(
                f"{where}: {', '.join(lacking)}'s metrics.json has no {metric!r}; gate it with "
                f"only: [the scenarios that have it] rather than write null"
            )


def load_baseline(path: Path) -> dict[str, dict[str, float | None]]:
    """The baseline file: scenario -> metric -> number or null; a malformed line names itself."""
    from uma.config.yamlfile import load_yaml

    data, lines = load_yaml(path)
    if not isinstance(data, dict):
        raise ConfigError(f"{lines.where(())}: expected a mapping of scenario -> metric -> value")
    out: dict[str, dict[str, float | None]] = {}
    for scenario, values in data.items():
        if not isinstance(values, dict):
            raise ConfigError(
                f"{lines.where((scenario,))}: expected a mapping of metric -> value, got {values!r}"
            )
        for metric, value in values.items():
            if value is not None and not _number(value):
                raise ConfigError(
                    f"{lines.where((scenario, metric))}: expected a number or null, got {value!r}"
                )
        out[str(scenario)] = {str(k): v for k, v in values.items()}
    return out


def _check(scenario: str, metric: str, tol: Tolerance, base: Any, now: Any) -> Check:
    def result(change: str, verdict: str) -> Check:
        return Check(scenario, metric, base, now, change, tol.describe(), verdict)

    if base is None:
        return result("", "ok" if now is None else "better")
    if not _number(now):
        return result("", "missing")
    delta = now - base
    change = (
        f"{delta / abs(base) * 100:+.2f} %"
        if tol.relative is not None and base
        else f"{delta:+.4g}"
    )
    worse_by = delta if tol.worse == "up" else -delta
    allowed = tol.allowed(base)
    if worse_by > allowed + 1e-12:
        return result(change, "REGRESSED")
    return result(change, "better" if -worse_by > allowed + 1e-12 else "ok")


def compare(
    suite: Suite,
    baseline: dict[str, dict[str, Any]],
    now: dict[str, dict[str, Any] | None],
) -> list[Check]:
    """One check per scenario and metric; `now[scenario]` None means the run left no results."""
    checks = []
    for scenario, metrics in now.items():
        base = baseline.get(scenario)
        if base is None:
            raise ConfigError(
                f"{suite.baseline_path}: no baseline for scenario {scenario!r} "
                f"(write one on purpose with --update)"
            )
        for metric, tol in suite.metrics_of(scenario).items():
            if metric not in base:
                raise ConfigError(
                    f"{suite.baseline_path} ({scenario}.{metric}): no baseline value "
                    f"(write one on purpose with --update)"
                )
            value = metric_value(metrics, metric)
            checks.append(_check(scenario, metric, tol, base[metric], value))
    return checks


def _shown(value: Any) -> str:
    return "-" if value is None else f"{value:.6g}"


def format_checks(checks: list[Check]) -> str:
    """The table: scenario, metric, baseline, now, change, tolerance, verdict."""
    head = ("scenario", "metric", "baseline", "now", "change", "tolerance", "verdict")
    rows = [head] + [
        (c.scenario, c.metric, _shown(c.baseline), _shown(c.now), c.change, c.tolerance, c.verdict)
        for c in checks
    ]
    widths = [max(len(row[i]) for row in rows) for i in range(len(head))]
    return "\n".join(
        "  ".join(cell.ljust(width) for cell, width in zip(row, widths, strict=True)).rstrip()
        for row in rows
    )


def baseline_yaml(suite: Suite, now: dict[str, dict[str, Any]]) -> str:
    """The baseline file's text for the current results (the metrics the suite gates)."""
    lines = [
        f"# Baseline of {suite.path.name}: written by `uma regress {suite.path.name} --update`.",
        "# Regenerate on purpose, and say why in the commit message.",
        f"# Machine class: {suite.machine} (a baseline belongs to a kind of machine too).",
    ]
    for scenario, metrics in now.items():
        lines.append(f"{scenario}:")
        for metric in suite.metrics_of(scenario):
            value = metric_value(metrics, metric)
            if value is not None and not _number(value):
                raise ConfigError(
                    f"{scenario}'s metrics.json ({metric}): expected a finite number or null "
                    f"for the baseline, got {value!r}"
                )
            lines.append(f"  {metric}: {'null' if value is None else repr(float(value))}")
    return "\n".join(lines) + "\n"
