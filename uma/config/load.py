"""Load a scenario file into a validated `Scenario`, or fail naming file, line and key."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from uma.config.retired import find_retired
from uma.config.scenario import Scenario
from uma.config.technologies import LABELS, technology_label
from uma.config.yamlfile import KeyLines, load_yaml
from uma.errors import ConfigError
from uma.paths import scenarios_dir

__all__ = ["load_scenario", "default_scenario_path", "scenario_from_dict"]

DEFAULT_SCENARIO = "stockholm-uppsala.yaml"


def default_scenario_path() -> Path:
    return scenarios_dir() / DEFAULT_SCENARIO


def _number(value: Any) -> str:
    """`100000.0` as `100000`, `1e-06` as `1e-06`: a bound's message reads like the file."""
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def _describe_error(error: dict[str, Any]) -> str:
    kind = error["type"]
    found = error.get("input")
    if kind == "extra_forbidden":
        return "unknown key"
    if kind == "missing":
        return "missing required key"
    found_text = repr(found)
    if len(found_text) > 60:
        found_text = found_text[:57] + "..."
    limits = error.get("ctx") or {}
    if kind == "less_than_equal":
        return f"{_number(found)} is above the maximum {_number(limits['le'])}"
    if kind == "greater_than_equal":
        return f"{_number(found)} is below the minimum {_number(limits['ge'])}"
    message = error["msg"]
    if kind == "value_error" and isinstance(found, dict | list | tuple):
        found_text = ""  # a section's check: its message names the values it compares
    if message.startswith("Value error, "):
        message = message[len("Value error, ") :]
    got = f", got {found_text}" if found_text else ""
    return f"{message[:1].lower()}{message[1:]}{got}"


def scenario_from_dict(data: Any, lines: KeyLines, *, base_dir: Path) -> Scenario:
    """Validate parsed YAML; errors name the line and key path. Paths resolve against `base_dir`."""
    from pydantic import ValidationError

    if not isinstance(data, dict):
        raise ConfigError(
            f"{lines.where(())}: expected a mapping of scenario keys, got {type(data).__name__}"
        )
    retired = find_retired(data)
    if retired is not None:
        path, why = retired
        raise ConfigError(f"{lines.where(path)}: {'.'.join(path)} is retired: {why}")
    try:
        scenario = Scenario.model_validate(data)
    except ValidationError as err:
        first = err.errors()[0]
        key_path = [part for part in first["loc"] if part not in ("function-after",)]
        more = f" (and {err.error_count() - 1} more)" if err.error_count() > 1 else ""
        raise ConfigError(f"{lines.where(key_path)}: {_describe_error(first)}{more}") from None
    scenario = scenario.resolved_paths(base_dir)
    _check_files(scenario, lines)
    _check_names(scenario, lines)
    return scenario


def _check_files(scenario: Scenario, lines: KeyLines) -> None:
    """Every file the scenario names is a regular file: a FIFO or a device would block the run
    or never end, a symlink loop would raise deep in `pathlib`."""
    import errno
    import os
    import stat

    wanted: list[tuple[tuple, str | None]] = [
        (
            ("source", "path"),
            scenario.source.path if scenario.source.kind in ("file", "yuv") else None,
        ),
        (("engine", "ladder"), scenario.engine.ladder),
        (("engine", "mbc", "description"), scenario.engine.mbc.description),
    ]
    wanted += [(("route", i, "trace"), seg.trace) for i, seg in enumerate(scenario.route)]
    wanted.append((("feedback", "trace"), scenario.feedback.trace))
    for key_path, path in wanted:
        if path is None:
            continue
        try:
            mode = os.stat(path).st_mode
        except OSError as err:
            found = "a symlink loop" if err.errno == errno.ELOOP else "no such file"
            raise ConfigError(
                f"{lines.where(key_path)}: expected an existing file, got {path!r} ({found})"
            ) from None
        if stat.S_ISDIR(mode):
            raise ConfigError(f"{lines.where(key_path)}: expected a file, got a folder {path!r}")
        if not stat.S_ISREG(mode):
            raise ConfigError(
                f"{lines.where(key_path)}: expected a regular file, got {path!r} "
                f"(a FIFO, socket or device)"
            )


def _check_names(scenario: Scenario, lines: KeyLines) -> None:
    route = scenario.route
    if scenario.feedback.trace is not None and (len(route) != 1 or route[0].trace is None):
        raise ConfigError(
            f"{lines.where(('feedback', 'trace'))}: expected a route of one trace segment "
            f"beside it (the uplink is read from that segment's offset_s), got {len(route)} "
            f"segment(s){'' if route[0].trace else ', the first generated'}"
        )
    for index, segment in enumerate(scenario.route):
        if segment.trace is None and not technology_label(segment.technology):
            raise ConfigError(
                f"{lines.where(('route', index, 'technology'))}: expected one of "
                f"{', '.join(LABELS)} (or a trace file), got {segment.technology!r}"
            )


def load_scenario(path: str | Path | None = None) -> Scenario:
    """Parse and validate a scenario file (the default scenario when `path` is None)."""
    path = Path(path) if path is not None else default_scenario_path()
    data, lines = load_yaml(path)
    return scenario_from_dict(data, lines, base_dir=path.resolve().parent)
