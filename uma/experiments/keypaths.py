"""Scenario key paths such as `engine.policy` or `route[1].trace`: parse, check, set.

No units of their own: a key path names a scenario key, and the key's name carries its unit.
A grid key is checked against the scenario schema before anything runs, so a typo is refused
with the experiment file's line instead of failing every point.
"""

from __future__ import annotations

import re
from typing import Any

__all__ = ["parse_key_path", "check_key_path", "set_key_path", "PATH_KEYS"]

_PART = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)")
# Keys whose values are file paths: relative values resolve against the experiment's folder.
PATH_KEYS = frozenset({"trace", "path", "ladder", "base"})


def parse_key_path(text: str) -> tuple[str | int, ...]:
    """`route[1].trace` -> `("route", 1, "trace")`; ValueError naming what is wrong."""
    parts: list[str | int] = []
    for piece in text.split("."):
        match = _PART.fullmatch(piece)
        if not match:
            raise ValueError(
                f"expected a key path such as engine.policy or route[1].trace, got {text!r}"
            )
        parts.append(match.group(1))
        parts += [int(i) for i in re.findall(r"\[(\d+)\]", match.group(2))]
    return tuple(parts)


def check_key_path(key_path: tuple[str | int, ...], base: dict[str, Any]) -> None:
    """Raise ValueError unless `key_path` names a scenario key (list indices within `base`)."""
    from typing import get_args, get_origin

    from uma.config.scenario import Scenario

    node: Any = Scenario
    data: Any = base
    walked = ""
    for part in key_path:
        if isinstance(part, int):
            items = data if isinstance(data, list) else []
            if get_origin(node) is not tuple or part >= len(items):
                raise ValueError(f"{walked} has no item [{part}] in the base scenario")
            node, data = get_args(node)[0], items[part]
            walked += f"[{part}]"
            continue
        if get_origin(node) is dict:  # e.g. downlink.technologies.GPRS: any name is a key
            node, data = get_args(node)[1], (data.get(part) if isinstance(data, dict) else None)
            walked += f".{part}" if walked else part
            continue
        model = _model_of(node)
        if model is None or part not in model.model_fields:
            known = ", ".join(sorted(model.model_fields)) if model is not None else "none"
            where = walked or "the scenario"
            raise ValueError(f"unknown key {part!r} in {where} (its keys: {known})")
        node = model.model_fields[part].annotation
        data = data.get(part) if isinstance(data, dict) else None
        walked += f".{part}" if walked else part


def _model_of(annotation: Any):
    """The pydantic model inside `annotation` (`X`, `X | None`), or None."""
    from typing import get_args

    from pydantic import BaseModel

    candidates = [annotation, *get_args(annotation)]
    for item in candidates:
        if isinstance(item, type) and issubclass(item, BaseModel):
            return item
    return None


def set_key_path(data: dict[str, Any], key_path: tuple[str | int, ...], value: Any) -> None:
    """Set `value` at `key_path` in plain YAML data, creating mappings on the way."""
    node: Any = data
    for part, following in zip(key_path, key_path[1:], strict=False):
        if isinstance(part, int):
            node = node[part]
        else:
            child = node.get(part)
            if child is None:
                child = [] if isinstance(following, int) else {}
                node[part] = child
            node = child
    node[key_path[-1]] = value
