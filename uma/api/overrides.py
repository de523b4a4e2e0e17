"""Key-path overrides of a scenario for the Python API, validated exactly as the YAML file is.

`uma.run("s.yaml", overrides={"engine.codec": "vp8"}, duration_s=6)`: each key is a key path as
an experiment's grid writes it (`engine.policy`, `route[1].trace`); a value replaces what the
file gives at that path (a mapping replaces the whole section, as in a sweep). The keys are
checked against the schema before the scenario is validated, and a bad key or value is one
`ConfigError` naming the key: `uma.run (engine.codec): expected ...`. Relative file paths given
as overrides resolve against the current folder; the file's own, against the file's folder.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from uma.config.scenario import Scenario
from uma.config.yamlfile import KeyLines
from uma.errors import ConfigError

__all__ = ["resolve_scenario", "override_pairs", "ORIGIN"]

ORIGIN = "uma.run"  # where an override came from, in messages


@dataclass(frozen=True)
class _OverrideLines(KeyLines):
    """Key lines of the base file, except that a key an override gives cites the override."""

    overridden: tuple[tuple, ...] = ()
    origin: str = ORIGIN

    def where(self, key_path) -> str:
        from uma.config.yamlfile import format_key_path

        key = tuple(key_path)
        if any(key[: len(given)] == given for given in self.overridden):
            return f"{self.origin} ({format_key_path(key)})"
        return super().where(key_path)


def _parsed_keys(
    overrides: Iterable[tuple[str, Any]], base: dict[str, Any], origin: str = ORIGIN
) -> list[tuple[tuple, Any]]:
    """(key path, value) of every override, each key checked against the schema; messages
    name `origin` as where the key came from."""
    from uma.experiments.keypaths import check_key_path, parse_key_path

    parsed: list[tuple[tuple, Any]] = []
    seen: dict[tuple, str] = {}
    for text, value in overrides:
        if not isinstance(text, str):
            raise ConfigError(f"{origin}: expected key paths such as engine.codec, got {text!r}")
        try:
            key_path = parse_key_path(text)
            check_key_path(key_path, base)
        except ValueError as err:
            raise ConfigError(f"{origin} ({text}): {err}") from None
        if key_path in seen:
            raise ConfigError(
                f"{origin} ({text}): given twice (also as {seen[key_path]!r}); give each key once"
            )
        seen[key_path] = text
        parsed.append((key_path, value))
    return parsed


def _plain(value: Any) -> Any:
    """`value` as YAML would give it: numpy scalars as Python numbers, tuples as lists."""
    import numpy as np

    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, list | tuple):
        return [_plain(item) for item in value]
    if isinstance(value, Mapping):
        return {key: _plain(item) for key, item in value.items()}
    return value


def _absolute(key_path: tuple, value: Any) -> Any:
    from uma.experiments.keypaths import PATH_KEYS

    value = _plain(value)
    if key_path[-1] in PATH_KEYS and isinstance(value, str | Path) and str(value):
        path = Path(value).expanduser()
        return str(path if path.is_absolute() else path.resolve())
    return value


def _base(scenario: Any) -> tuple[dict[str, Any], KeyLines, Path]:
    """The plain data, key lines and folder of `scenario` (a path or a `Scenario`)."""
    from uma.config.yamlfile import load_yaml

    if isinstance(scenario, Scenario):
        where = f"{ORIGIN} (Scenario {scenario.name})"
        return scenario.model_dump(mode="json"), KeyLines(Path(where)), Path.cwd()
    if isinstance(scenario, str | Path) and str(scenario):
        path = Path(scenario)
        data, lines = load_yaml(path)
        if not isinstance(data, dict):
            raise ConfigError(f"{lines.where(())}: expected a mapping of scenario keys")
        return data, lines, path.resolve().parent
    raise ConfigError(
        f"{ORIGIN}: expected a scenario file path or a uma.config.Scenario, got "
        f"{type(scenario).__name__} {scenario!r:.60}"
    )


def override_pairs(overrides: Any, keys: Mapping[str, Any]) -> list[tuple[str, Any]]:
    """The `overrides=` mapping's items, then the keyword arguments'; a key given twice kept twice
    (so that `resolve_scenario` refuses it rather than one silently winning)."""
    if overrides is None:
        return list(keys.items())
    if not isinstance(overrides, Mapping):
        raise ConfigError(
            f"{ORIGIN}: expected overrides= a mapping of key paths to values, such as "
            f"{{'engine.codec': 'vp8'}}, got {type(overrides).__name__}"
        )
    return [*overrides.items(), *keys.items()]


def resolve_scenario(
    scenario: Any, overrides: Iterable[tuple[str, Any]] = (), *, origin: str = ORIGIN
) -> Scenario:
    """`scenario` (a path or a `Scenario`) with `overrides` (key path, value) applied and
    validated as YAML is; a bad override's message names `origin` (`uma run --set` gives
    "--set") and the key."""
    from uma.config.load import scenario_from_dict
    from uma.experiments.keypaths import set_key_path

    overrides = list(overrides)
    if isinstance(scenario, Scenario) and not overrides:
        return scenario
    data, lines, folder = _base(scenario)
    parsed = _parsed_keys(overrides, data, origin)
    for key_path, value in parsed:
        set_key_path(data, key_path, _absolute(key_path, value))
    overridden = tuple(key for key, _ in parsed)
    lines = _OverrideLines(lines.path, lines.lines, overridden=overridden, origin=origin)
    return scenario_from_dict(data, lines, base_dir=folder)
