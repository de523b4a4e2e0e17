"""Read a YAML file and remember where each key came from, for error messages.

`load_yaml(path)` returns the plain data and a `KeyLines` lookup from a key path such as
`("route", 2, "duration_s")` to the 1-based line that holds it, so a schema error can say
`scenarios/x.yaml:14 (route[2].duration_s): expected ...`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from uma.errors import ConfigError

__all__ = ["KeyLines", "load_yaml", "format_key_path"]


@dataclass(frozen=True)
class KeyLines:
    """Map key paths to the line they start on; unknown paths fall back to their parent's line."""

    path: Path
    lines: dict[tuple, int] = field(default_factory=dict)

    def line_of(self, key_path: Sequence[Any]) -> int | None:
        key = tuple(key_path)
        while key:
            if key in self.lines:
                return self.lines[key]
            key = key[:-1]
        return self.lines.get(())

    def where(self, key_path: Sequence[Any]) -> str:
        """`FILE:LINE (key.path)` for messages."""
        line = self.line_of(key_path)
        location = f"{self.path}:{line}" if line else str(self.path)
        dotted = format_key_path(key_path)
        return f"{location} ({dotted})" if dotted else location


def format_key_path(key_path: Sequence[Any]) -> str:
    """`("route", 2, "duration_s")` -> `route[2].duration_s`."""
    out = ""
    for part in key_path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
    return out


def _walk(node: Any, key_path: tuple, lines: dict[tuple, int], path: Path) -> None:
    import yaml

    lines[key_path] = node.start_mark.line + 1
    if isinstance(node, yaml.MappingNode):
        seen: dict[Any, int] = {}
        for key_node, value_node in node.value:
            key = key_node.value
            line = key_node.start_mark.line + 1
            if key in seen:
                # yaml.safe_load keeps the last of duplicate keys silently; a typo'd copy of a
                # key would then override the one the user reads.
                dotted = format_key_path(key_path + (key,))
                raise ConfigError(
                    f"{path}:{line} ({dotted}): duplicate key, already given on line {seen[key]}"
                )
            seen[key] = line
            _walk(value_node, key_path + (key,), lines, path)
            # Point at the key's own line: a nested mapping's value starts on the next line.
            lines[key_path + (key,)] = key_node.start_mark.line + 1
    elif isinstance(node, yaml.SequenceNode):
        for index, item in enumerate(node.value):
            _walk(item, key_path + (index,), lines, path)


def load_yaml(path: str | Path) -> tuple[Any, KeyLines]:
    """Parse `path`; a missing file or a YAML syntax error raises `ConfigError` naming the line."""
    import yaml

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ConfigError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as err:
        raise ConfigError(f"{path}: cannot read as UTF-8 text ({err})") from None
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
        data = yaml.safe_load(text)
    except yaml.MarkedYAMLError as err:
        mark = err.problem_mark
        line = f":{mark.line + 1}" if mark is not None else ""
        raise ConfigError(f"{path}{line}: invalid YAML: {err.problem}") from None
    except yaml.YAMLError as err:  # a ReaderError: a character YAML does not allow
        position = getattr(err, "position", None)
        line = f":{text[:position].count(chr(10)) + 1}" if isinstance(position, int) else ""
        character = getattr(err, "character", None)
        what = (
            f"expected text, got character #x{character:04x} ({err.reason})"
            if isinstance(character, int)
            else " ".join(str(err).split())
        )
        raise ConfigError(f"{path}{line}: invalid YAML: {what}") from None
    lines: dict[tuple, int] = {}
    if node is not None:
        _walk(node, (), lines, path)
    return data, KeyLines(path, lines)
