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


@dataclass(frozen=True)
class _File:
    """An experiment file's top level, checked: where it is, its base scenario, its sections."""

    path: Path
    lines: KeyLines
    base_path: Path
    base_data: dict
    base_lines: KeyLines
    name: str
    repeat: int
    grid: dict
    fixed: dict

    @property
    def folder(self) -> Path:
        return self.path.resolve().parent

    def key_path(self, section: str, text: Any) -> tuple:
        """`text` under `section` as a key path of the base scenario; `ConfigError` otherwise."""
        from uma.experiments.keypaths import check_key_path, parse_key_path

        where = self.lines.where((section, text))
        if not isinstance(text, str):
            raise ConfigError(f"{where}: expected a key path, got {text!r}")
        try:
            parsed = parse_key_path(text)
            check_key_path(parsed, self.base_data)
        except ValueError as err:
            raise ConfigError(f"{where}: {err}") from None
        return parsed

    def value_for(self, parsed: tuple, value: Any) -> Any:
        """`value` as the scenario takes it (a file path relative to the experiment file)."""
        from uma.experiments.keypaths import PATH_KEYS

        return _absolute(value, self.folder) if parsed[-1] in PATH_KEYS else value


def _checked_name(data: dict, lines: KeyLines, path: Path) -> str:
    name = data.get("name", path.stem)
    # The default results folder is results/<name>: a name, not a path ("../x", "a/b").
    named = re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,99}", name) if isinstance(name, str) else 0
    if "name" in data and not named:
        shown = repr(name) if len(repr(name)) <= 60 else repr(name)[:57] + "..."
        raise ConfigError(
            f"{lines.where(('name',))}: expected a name of letters, digits, '_', '.' and '-' "
            f"(at most 100, not starting with a punctuation mark), got {shown}"
        )
    return name


def _read_file(path: Path) -> _File:
    """The experiment file's top level, each key checked, and its base scenario's data."""
    from uma.config.yamlfile import load_yaml

    data, lines = load_yaml(path)
    if not isinstance(data, dict):
        raise ConfigError(f"{lines.where(())}: expected a mapping with base and grid")
    for key in data:
        if key not in _TOP_KEYS:
            raise ConfigError(
                f"{lines.where((key,))}: unknown key, expected one of {', '.join(_TOP_KEYS)}"
            )
    if "base" not in data or not isinstance(data["base"], str):
        raise ConfigError(f"{lines.where(('base',))}: expected base: the path of a scenario file")
    base_path = Path(_absolute(data["base"], path.resolve().parent))
    base_data, base_lines = load_yaml(base_path)
    if not isinstance(base_data, dict):
        raise ConfigError(f"{base_lines.where(())}: expected a mapping of scenario keys")
    name = _checked_name(data, lines, path)
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
    return _File(path, lines, base_path, base_data, base_lines, name, repeat, grid, fixed)


def _axes(file: _File) -> list[tuple[str, tuple, list]]:
    """The grid's (key path text, parsed key path, values), each list checked, and the count
    of runs bounded by `MAX_POINTS`."""
    axes = []
    for text, values in file.grid.items():
        parsed = file.key_path("grid", text)
        if not isinstance(values, list) or not values:
            raise ConfigError(
                f"{file.lines.where(('grid', text))}: expected a non-empty list of values, "
                f"got {values!r}"
            )
        seen: dict[str, int] = {}
        for i, value in enumerate(values):
            first = seen.setdefault(_same_key(file.value_for(parsed, value)), i)
            if first != i:
                raise ConfigError(
                    f"{file.lines.where(('grid', text, i))}: duplicate value {value!r} of "
                    f"{text}, already item [{first}]; each value runs once (use repeat: for seeds)"
                )
        axes.append((text, parsed, values))
    count = file.repeat
    for _, _, values in axes:
        count *= len(values)
    if count > MAX_POINTS:
        sizes = " x ".join(str(len(values)) for _, _, values in axes)
        repeats = f" x repeat {file.repeat}" if file.repeat > 1 else ""
        raise ConfigError(
            f"{file.lines.where(('grid',))}: expected at most {MAX_POINTS} runs, got {count} "
            f"({sizes} values{repeats}); split the experiment"
        )
    return axes


def _point_scenario(file: _File, settings: list, rep: int, lines: KeyLines, shown: str):
    """The scenario of one point: the base with `settings` ((parsed key path, value) pairs, the
    grid's last) and the repeat's seed; `ConfigError` naming the point otherwise."""
    from uma.config.load import scenario_from_dict
    from uma.experiments.keypaths import set_key_path

    point_data = copy.deepcopy(file.base_data)
    for parsed, value in settings:
        set_key_path(point_data, parsed, file.value_for(parsed, value))
    seed = point_data.get("seed", 0)
    if rep:
        point_data["seed"] = (seed if isinstance(seed, int) else 0) + rep
    try:
        return scenario_from_dict(point_data, lines, base_dir=file.base_path.resolve().parent)
    except ConfigError as err:
        raise ConfigError(f"{err} (grid point {shown})") from None


def _points(file: _File, fixed_paths: list, axes: list) -> list[Point]:
    """Every grid combination and repeat as a validated point; two equal runs are refused."""
    shipped = shipped_digests()  # once: every point reads the same shipped data
    points: list[Point] = []
    by_hash: dict[str, Point] = {}
    for combo in itertools.product(*(enumerate(values) for _, _, values in axes)):
        given = tuple((parsed, ("set", text)) for parsed, text, _ in fixed_paths) + tuple(
            (parsed, ("grid", text, i))
            for (text, parsed, _), (i, _) in zip(axes, combo, strict=True)
        )
        # Grid keys last, so a grid key below a `set` key cites the grid.
        lines = _PointLines(
            file.base_lines.path, file.base_lines.lines, experiment=file.lines, given=given[::-1]
        )
        values = {text: value for (text, _, _), (_, value) in zip(axes, combo, strict=True)}
        shown = ", ".join(f"{k}={v!r}" for k, v in values.items())
        settings = [(parsed, value) for parsed, _, value in fixed_paths] + [
            (parsed, value) for (_, parsed, _), (_, value) in zip(axes, combo, strict=True)
        ]
        for rep in range(file.repeat):
            scenario = _point_scenario(file, settings, rep, lines, shown)
            point = Point(
                len(points), values, rep, scenario, scenario_hash(scenario, shipped=shipped)
            )
            twin = by_hash.setdefault(point.hash, point)
            if twin is not point:
                raise ConfigError(
                    f"{file.lines.where(('grid',))}: grid points {twin.index} and {point.index} "
                    f"({shown}, repeat {rep}) are the same run (equal scenarios and files); "
                    f"each point must differ"
                )
            points.append(point)
    return points


def load_experiment(path: str | Path) -> Experiment:
    """Parse an experiment file and expand its grid into validated points."""
    file = _read_file(Path(path))
    fixed_paths = [(file.key_path("set", k), k, v) for k, v in file.fixed.items()]
    axes = _axes(file)
    points = _points(file, fixed_paths, axes)
    return Experiment(file.name, file.path, tuple(text for text, _, _ in axes), tuple(points))
