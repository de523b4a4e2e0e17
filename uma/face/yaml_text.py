"""YAML (and JSON) files of the face room, read once, with PyYAML's errors put on one line.

PyYAML's own messages run over several lines (context, a quoted snippet, a caret); a user
needs `FILE:LINE: what was expected, what was found`. `read_yaml` gives that for syntax errors,
bad characters, binary data and nesting too deep to read, and returns the composed node too,
so callers can name the line of any key.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from uma.errors import FaceError
from uma.paths import read_capped

__all__ = ["read_yaml", "yaml_error_text"]

MAX_YAML_BYTES = 16 * 1024 * 1024  # a points file is a few kB, the wireframe about 100 kB


def read_yaml(path: str | Path, *, what: str, loader: type | None = None) -> tuple[Any, Any]:
    """(data, node) of the YAML/JSON file at `path` (a `what`, for messages); `node` is None
    for an empty document. `loader` defaults to `yaml.SafeLoader` (pass a subclass of it)."""
    import yaml

    path = Path(path)
    raw = read_capped(path, max_bytes=MAX_YAML_BYTES, error=FaceError, what=what)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as err:
        raise FaceError(
            f"{path}: expected {what} (UTF-8 text), got binary data (byte {err.start})"
        ) from None
    if path.suffix.lower() == ".json":
        return _json(path, text, what), _json_node(text)
    reader = None
    try:
        reader = (loader or yaml.SafeLoader)(text)  # checks the characters at once
        node = reader.get_single_node()
        data = reader.construct_document(node) if node is not None else None
    except yaml.YAMLError as err:
        raise FaceError(f"{path}:{yaml_error_text(err, text)}") from None
    except RecursionError:
        raise FaceError(f"{path}: expected {what}, got nesting too deep to read") from None
    finally:
        if reader is not None:
            reader.dispose()
    return data, node


def _json(path: Path, text: str, what: str) -> Any:
    """JSON by the json module: YAML refuses the tab indentation JSON writers use."""
    import json

    def pairs(items: list[tuple[str, Any]]) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for key, value in items:
            if key in out:
                raise FaceError(f"{path}: {key!r}: duplicate key in one object")
            out[key] = value
        return out

    try:
        return json.loads(text, object_pairs_hook=pairs)
    except json.JSONDecodeError as err:
        raise FaceError(
            f"{path}:{err.lineno}: invalid JSON: {err.msg[:1].lower()}{err.msg[1:]} "
            f"(column {err.colno})"
        ) from None
    except RecursionError:
        raise FaceError(f"{path}: expected {what}, got nesting too deep to read") from None


def _json_node(text: str) -> Any:
    """The YAML node of valid JSON, for key lines (tabs are only whitespace in JSON)."""
    import yaml

    try:
        return yaml.compose(text.replace("\t", " "), Loader=yaml.SafeLoader)
    except (yaml.YAMLError, RecursionError):
        return None


def yaml_error_text(err: Exception, text: str = "") -> str:
    """`LINE: invalid YAML: PROBLEM (CONTEXT on line N)` from a PyYAML error, on one line."""
    problem = getattr(err, "problem", None)
    mark = getattr(err, "problem_mark", None)
    if problem is None:  # a ReaderError: a character YAML does not allow
        position = getattr(err, "position", None)
        line = text[:position].count("\n") + 1 if isinstance(position, int) else 1
        character = getattr(err, "character", None)
        found = (
            f"character #x{character:04x}"
            if isinstance(character, int)
            else "an unreadable character"
        )
        return f"{line}: expected YAML text, got {found}"
    line = mark.line + 1 if mark is not None else 1
    problem = problem.replace(", but found ", ", got ").replace(", but got ", ", got ")
    problem = problem.replace("'<stream end>'", "the end of the file")
    context = getattr(err, "context", None)
    context_mark = getattr(err, "context_mark", None)
    where = ""
    if context:
        on = context_mark.line + 1 if context_mark is not None else None
        where = f" ({context} on line {on})" if on and on != line else f" ({context})"
    return " ".join(f"{line}: invalid YAML: {problem}{where}".split())
