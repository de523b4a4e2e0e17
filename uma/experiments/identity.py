"""A sweep point's identity: the hash of its resolved scenario and of every file it reads.

Two points are the same run only when their scenarios are equal and each file they name
(traces, the source video, the face description or points file, the ladder) has the same bytes.
A YAML or JSON file's own references (a points file's `video:`) count too: a string value that
names an existing file, relative to that file's folder or `shared:PATH` under the shared data
folder, is read in turn. So a trace edited in place makes its points run again. The shipped
data a run reads without naming it (the default ladder, the face model, the talking head's
points, all under `codecs/`) is hashed too. The code itself is not: after changing uma, sweep
into a new folder.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

__all__ = ["scenario_hash", "file_digests", "shipped_digests"]

_FOLLOWED = (".yaml", ".yml", ".json")  # text files whose values may name further files
_MAX_DEPTH = 3
_SHARED_PREFIX = "shared:"
# (path, size, mtime_ns, ctime_ns, inode) -> SHA-256: a sweep of many points over one video reads it once.
_CACHE: dict[tuple[str, int, int, int, int], str] = {}


def _digest(path: Path) -> str | None:
    try:
        stat = path.stat()
        key = (str(path), stat.st_size, stat.st_mtime_ns, stat.st_ctime_ns, stat.st_ino)
        if key not in _CACHE:
            sha = hashlib.sha256()
            with open(path, "rb") as handle:
                for block in iter(lambda: handle.read(1 << 20), b""):
                    sha.update(block)
            _CACHE[key] = sha.hexdigest()
        return _CACHE[key]
    except OSError:
        return None  # unreadable here: validation has said so, or the run will


def _strings(data: Any):
    if isinstance(data, str):
        yield data
    elif isinstance(data, dict):
        for value in data.values():
            yield from _strings(value)
    elif isinstance(data, list | tuple):
        for value in data:
            yield from _strings(value)


def _as_file(value: str, folder: Path | None) -> Path | None:
    """The existing regular file `value` names (absolute, `shared:`, or relative to `folder`)."""
    if not value or len(value) > 4096 or "\n" in value:
        return None
    if folder is None and not value.startswith(("/", "~", _SHARED_PREFIX)):
        return None  # the scenario's paths are absolute once resolved
    if value.startswith(_SHARED_PREFIX):
        from uma.paths import shared_data_dir

        path = shared_data_dir() / value[len(_SHARED_PREFIX) :]
    else:
        path = Path(value).expanduser()
        if not path.is_absolute():
            if folder is None:
                return None
            path = folder / path
    try:
        return path.resolve() if path.is_file() else None
    except OSError:
        return None


def _references(path: Path) -> list[str]:
    """The strings of YAML or JSON file `path`, read within the bounds a scenario is read in
    (`uma.config.yamlfile`): an alias bomb or a huge file names nothing, and the run that
    reads it refuses it in one line."""
    if path.suffix.lower() not in _FOLLOWED:
        return []
    from uma.config.yamlfile import MAX_YAML_BYTES, parse_yaml_bounded
    from uma.errors import ConfigError
    from uma.paths import read_capped

    try:
        text = read_capped(path, max_bytes=MAX_YAML_BYTES, error=ConfigError).decode("utf-8")
        return list(_strings(parse_yaml_bounded(text, path)[0]))  # JSON is YAML too
    except (ConfigError, UnicodeDecodeError, RecursionError):
        return []  # a file the run cannot read either; its bytes are in the hash already


def file_digests(data: Any) -> dict[str, str]:
    """Path -> SHA-256 of every file named by an absolute path in `data`, and what those name."""
    digests: dict[str, str] = {}
    todo = [(path, 0) for value in _strings(data) if (path := _as_file(value, None))]
    while todo:
        path, depth = todo.pop()
        if str(path) in digests:
            continue
        digest = _digest(path)
        if digest is None:
            continue
        digests[str(path)] = digest
        if depth < _MAX_DEPTH:
            for value in _references(path):
                found = _as_file(value, path.parent)
                if found is not None:
                    todo.append((found, depth + 1))
    return dict(sorted(digests.items()))


def shipped_digests() -> dict[str, str]:
    """SHA-256 of every file under `codecs/`, keyed by its path there (not where the clone is)."""
    from uma.paths import codecs_dir

    root = codecs_dir()
    digests = {}
    for path in sorted(root.rglob("*")) if root.is_dir() else []:
        if path.is_file() and (digest := _digest(path)) is not None:
            digests[f"codecs/{path.relative_to(root).as_posix()}"] = digest
    return digests


def scenario_hash(scenario, *, shipped: dict[str, str] | None = None) -> str:
    """16 hex digits of SHA-256 over the resolved scenario and the contents of the files it reads.

    `shipped` is `shipped_digests()`, passed in to hash many points against one reading of it.

    `metrics.workers` does not change results (see `MetricsConfig`), so it is not part of a
    point's identity.
    """
    data = scenario.model_dump(mode="json")
    data["metrics"].pop("workers", None)
    files = file_digests(data) | (shipped_digests() if shipped is None else shipped)
    text = json.dumps({"scenario": data, "files": files}, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]
