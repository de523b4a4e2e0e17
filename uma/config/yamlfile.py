"""Read a YAML file and remember where each key came from, for error messages.

`load_yaml(path)` returns the plain data and a `KeyLines` lookup from a key path such as
`("route", 2, "duration_s")` to the 1-based line that holds it, so a schema error can say
`scenarios/x.yaml:14 (route[2].duration_s): expected ...`.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from uma.errors import ConfigError

__all__ = ["KeyLines", "load_yaml", "format_key_path", "parse_yaml_bounded", "MAX_YAML_BYTES"]

# What a configuration file (scenario, ladder, suite, experiment, points file) may hold. The
# largest shipped is 14 KB; the bounds keep a hostile file (an alias bomb, a 1,000-deep
# nesting, /dev/zero) from running out of memory or recursion before it is refused.
MAX_YAML_BYTES = 8 * 2**20
MAX_YAML_DEPTH = 64  # nested mappings and lists
MAX_YAML_NODES = 200_000  # values once every alias is expanded
MAX_YAML_ALIASES = 1_000  # uses of `*anchor`


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


_EXPONENT = re.compile(r"^[-+]?[0-9][0-9_]*(\.[0-9_]*)?[eE][-+]?[0-9]+$")


def _bounded_loader(text: str, path: Path):
    """A SafeLoader whose composer refuses nesting deeper than `MAX_YAML_DEPTH` and more than
    `MAX_YAML_ALIASES` alias uses, each with a `ConfigError` naming the line."""
    import yaml

    class Loader(yaml.SafeLoader):
        depth = 0
        aliases = 0

        def compose_node(self, parent, index):
            if self.check_event(yaml.AliasEvent):
                Loader.aliases += 1
                if Loader.aliases > MAX_YAML_ALIASES:
                    line = self.peek_event().start_mark.line + 1
                    raise ConfigError(
                        f"{path}:{line}: more than {MAX_YAML_ALIASES} aliases (*name), "
                        f"expected a configuration, not a file that expands without bound"
                    )
            if not self.check_event(yaml.SequenceStartEvent, yaml.MappingStartEvent):
                return super().compose_node(parent, index)
            Loader.depth += 1
            try:
                if Loader.depth > MAX_YAML_DEPTH:
                    line = self.peek_event().start_mark.line + 1
                    raise ConfigError(
                        f"{path}:{line}: nested more than {MAX_YAML_DEPTH} levels deep"
                    )
                return super().compose_node(parent, index)
            finally:
                Loader.depth -= 1

    # YAML 1.2 reads `1e5` and `1e-05` as numbers; PyYAML's 1.1 rules wanted a dot (`1.0e5`)
    # and read them as text, which the schema then refused as "not a number".
    Loader.add_implicit_resolver("tag:yaml.org,2002:float", _EXPONENT, list("-+0123456789"))
    return Loader(text)


def _expanded_size(node: Any, path: Path) -> int:
    """How many nodes `node` holds once aliases are expanded (a shared node counts each time)."""
    import yaml

    sizes: dict[int, int] = {}

    def size(item) -> int:
        if id(item) in sizes:
            return sizes[id(item)]
        total = 1
        if isinstance(item, yaml.MappingNode):
            total += sum(size(k) + size(v) for k, v in item.value)
        elif isinstance(item, yaml.SequenceNode):
            total += sum(size(v) for v in item.value)
        sizes[id(item)] = total = min(total, MAX_YAML_NODES + 1)
        return total

    if size(node) > MAX_YAML_NODES:
        raise ConfigError(
            f"{path}: expands to more than {MAX_YAML_NODES} values once its aliases (*name) "
            f"are expanded, expected a configuration"
        )
    return sizes[id(node)]


def parse_yaml_bounded(text: str, path: str | Path) -> tuple[Any, Any]:
    """The data and the composed node of YAML `text`; errors name `path` and the line.

    Depth, alias uses and the expanded size are bounded (`MAX_YAML_*`), so no file runs out
    of memory or recursion before it is refused.
    """
    import yaml

    path = Path(path)
    loader = None
    try:
        loader = _bounded_loader(text, path)  # its reader checks every character at once
        node = loader.get_single_node()
        if node is None:
            return None, None
        _expanded_size(node, path)
        return loader.construct_document(node), node
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
    except RecursionError:  # a bound above should have caught it first
        raise ConfigError(f"{path}: nested too deeply to read") from None
    finally:
        if loader is not None:
            loader.dispose()


def load_yaml(path: str | Path) -> tuple[Any, KeyLines]:
    """Parse `path`; a missing file or a YAML syntax error raises `ConfigError` naming the line.

    Only a regular file of at most `MAX_YAML_BYTES` is read (a FIFO, a device or a symlink
    loop is refused in one line); see `parse_yaml_bounded` for the other bounds.
    """
    from uma.paths import read_capped

    path = Path(path)
    data = read_capped(path, max_bytes=MAX_YAML_BYTES, error=ConfigError, what="file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise ConfigError(f"{path}: cannot read as UTF-8 text ({err})") from None
    data, node = parse_yaml_bounded(text, path)
    lines: dict[tuple, int] = {}
    if node is not None:
        _walk(node, (), lines, path)
    return data, KeyLines(path, lines)
