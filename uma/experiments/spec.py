"""An experiment file: a base scenario and a grid over its keys, expanded into points.

```yaml
name: policy-vs-playout
base: ../scenarios/stockholm-uppsala.yaml   # relative to this file
set: {duration_s: 30}                       # optional: the same keys for every point
grid:                                        # key path -> the values to try
  engine.policy: [throughput, oracle]
  receiver.playout_delay_ms: [150, 300, 600]
  route[1].trace: [a.log, b.log]             # paths relative to this file
repeat: 2                                    # optional: seeds seed, seed + 1, ... per point
```

Every point is validated before anything runs (an unknown key, an empty grid, a value given
twice, a value the schema refuses: one `ConfigError` naming the experiment file's line and key).
A grid of more than `MAX_POINTS` runs is refused before it is expanded. A point's identity is the
hash of its fully resolved scenario and of the contents of the files it reads (see
`uma.experiments.identity`), which makes a sweep resumable.
"""

from __future__ import annotations

import copy
import itertools
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from uma.config.scenario import Scenario
from uma.config.yamlfile import KeyLines
from uma.errors import ConfigError
from uma.experiments.identity import scenario_hash, shipped_digests

__all__ = ["Experiment", "Point", "load_experiment", "scenario_hash", "MAX_POINTS"]

_TOP_KEYS = ("name", "description", "base", "set", "grid", "repeat")
# Runs (grid combinations times repeats) one experiment may hold: beyond this, validating the
# points alone takes minutes and the memory grows with them; split the experiment instead.
MAX_POINTS = 10_000


@dataclass(frozen=True)
class Point:
    """One run of a sweep: its grid values, repeat number, resolved scenario and its hash."""

    index: int
    values: dict[str, Any]
    repeat: int
    scenario: Scenario
    hash: str


@dataclass(frozen=True)
class Experiment:
    name: str
    path: Path
    grid_keys: tuple[str, ...]
    points: tuple[Point, ...]


@dataclass(frozen=True)
class _PointLines(KeyLines):
    """A point's key lines: a key the grid or `set` gives cites the experiment file's line."""

    experiment: KeyLines | None = None
    given: tuple[tuple[tuple, tuple], ...] = ()  # (scenario key path, experiment key path)

    def where(self, key_path) -> str:
        key = tuple(key_path)
        for parsed, origin in self.given:
            if key[: len(parsed)] == parsed and self.experiment is not None:
                return self.experiment.where(origin + key[len(parsed) :])
        return super().where(key_path)


def _same_key(value: Any) -> str:
    """Equal grid values give equal keys (150 and 150 alike, mappings in any order)."""
    return json.dumps(value, sort_keys=True, default=str)


def _absolute(value: Any, folder: Path) -> Any:
    if isinstance(value, str) and value:
        path = Path(value).expanduser()
        return str(path if path.is_absolute() else (folder / path).resolve())
    return value


def load_experiment(path: str | Path) -> Experiment:
    """Parse an experiment file and expand its grid into validated points."""
    from uma.config.load import scenario_from_dict
    from uma.config.yamlfile import load_yaml
    from uma.experiments.keypaths import PATH_KEYS, check_key_path, parse_key_path, set_key_path

    path = Path(path)
    data, lines = load_yaml(path)
    folder = path.resolve().parent
    if not isinstance(data, dict):
        raise ConfigError(f"{lines.where(())}: expected a mapping with base and grid")
    for key in data:
        if key not in _TOP_KEYS:
            raise ConfigError(
                f"{lines.where((key,))}: unknown key, expected one of {', '.join(_TOP_KEYS)}"
            )
    if "base" not in data or not isinstance(data["base"], str):
        raise ConfigError(f"{lines.where(('base',))}: expected base: the path of a scenario file")
    base_path = Path(_absolute(data["base"], folder))
    base_data, base_lines = load_yaml(base_path)
    if not isinstance(base_data, dict):
        raise ConfigError(f"{base_lines.where(())}: expected a mapping of scenario keys")
    name = data.get("name", path.stem)
    # The default results folder is results/<name>: a name, not a path ("../x", "a/b").
    named = re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,99}", name) if isinstance(name, str) else 0
    if "name" in data and not named:
        shown = repr(name) if len(repr(name)) <= 60 else repr(name)[:57] + "..."
        raise ConfigError(
            f"{lines.where(('name',))}: expected a name of letters, digits, '_', '.' and '-' "
            f"(at most 100, not starting with a punctuation mark), got {shown}"
        )
    repeat = data.get("repeat", 1)
    if isinstance(repeat, bool) or not isinstance(repeat, int) or repeat < 1:
        raise ConfigError(
            f"{lines.where(('repeat',))}: expected a positive integer, got {repeat!r}"
        )

    grid = data.get("grid")
    if not isinstance(grid, dict) or not grid:
        raise ConfigError(
            f"{lines.where(('grid',))}: expected a non-empty mapping of key paths to lists of "
            f"values, got {grid!r}"
        )
    fixed = data.get("set") or {}
    if not isinstance(fixed, dict):
        raise ConfigError(f"{lines.where(('set',))}: expected a mapping of key paths to values")

    def key_path(section: str, text: Any) -> tuple:
        where = lines.where((section, text))
        if not isinstance(text, str):
            raise ConfigError(f"{where}: expected a key path, got {text!r}")
        try:
            parsed = parse_key_path(text)
            check_key_path(parsed, base_data)
        except ValueError as err:
            raise ConfigError(f"{where}: {err}") from None
        return parsed

    def value_for(parsed: tuple, value: Any) -> Any:
        return _absolute(value, folder) if parsed[-1] in PATH_KEYS else value

    fixed_paths = [(key_path("set", k), k, v) for k, v in fixed.items()]
    axes = []
    for text, values in grid.items():
        parsed = key_path("grid", text)
        if not isinstance(values, list) or not values:
            raise ConfigError(
                f"{lines.where(('grid', text))}: expected a non-empty list of values, got {values!r}"
            )
        seen: dict[str, int] = {}
        for i, value in enumerate(values):
            first = seen.setdefault(_same_key(value_for(parsed, value)), i)
            if first != i:
                raise ConfigError(
                    f"{lines.where(('grid', text, i))}: duplicate value {value!r} of {text}, "
                    f"already item [{first}]; each value runs once (use repeat: for seeds)"
                )
        axes.append((text, parsed, values))
    count = repeat
    for _, _, values in axes:
        count *= len(values)
    if count > MAX_POINTS:
        sizes = " x ".join(str(len(values)) for _, _, values in axes)
        raise ConfigError(
            f"{lines.where(('grid',))}: expected at most {MAX_POINTS} runs, got {count} "
            f"({sizes} values{f' x repeat {repeat}' if repeat > 1 else ''}); split the experiment"
        )

    shipped = shipped_digests()  # once: every point reads the same shipped data
    points: list[Point] = []
    by_hash: dict[str, Point] = {}
    base_dir = base_path.resolve().parent
    for combo in itertools.product(*(enumerate(values) for _, _, values in axes)):
        given = tuple((parsed, ("set", text)) for parsed, text, _ in fixed_paths) + tuple(
            (parsed, ("grid", text, i))
            for (text, parsed, _), (i, _) in zip(axes, combo, strict=True)
        )
        # Grid keys last, so a grid key below a `set` key cites the grid.
        point_lines = _PointLines(
            base_lines.path, base_lines.lines, experiment=lines, given=given[::-1]
        )
        values = {text: value for (text, _, _), (_, value) in zip(axes, combo, strict=True)}
        shown = ", ".join(f"{k}={v!r}" for k, v in values.items())
        for rep in range(repeat):
            point_data = copy.deepcopy(base_data)
            for parsed, _, value in fixed_paths:
                set_key_path(point_data, parsed, value_for(parsed, value))
            for (_, parsed, _), (_, value) in zip(axes, combo, strict=True):
                set_key_path(point_data, parsed, value_for(parsed, value))
            seed = point_data.get("seed", 0)
            if rep:
                point_data["seed"] = (seed if isinstance(seed, int) else 0) + rep
            try:
                scenario = scenario_from_dict(point_data, point_lines, base_dir=base_dir)
            except ConfigError as err:
                raise ConfigError(f"{err} (grid point {shown})") from None
            digest = scenario_hash(scenario, shipped=shipped)
            point = Point(len(points), values, rep, scenario, digest)
            twin = by_hash.setdefault(point.hash, point)
            if twin is not point:
                raise ConfigError(
                    f"{lines.where(('grid',))}: grid points {twin.index} and {point.index} "
                    f"({shown}, repeat {rep}) are the same run (equal scenarios and files); "
                    f"each point must differ"
                )
            points.append(point)
    return Experiment(name, path, tuple(text for text, _, _ in axes), tuple(points))
