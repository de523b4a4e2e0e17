"""Where the project's data folders live (`codecs/`, `scenarios/`, `traces/` at the project root),
and `read_capped`, the one way a user's file is read whole (bounded, regular files only).

The package is installed in editable mode from the clone, so the data folders sit beside it.
`UMA_HOME` overrides the root, for an installed copy that keeps its data elsewhere.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

__all__ = [
    "project_root",
    "codecs_dir",
    "scenarios_dir",
    "traces_dir",
    "shared_data_dir",
    "read_capped",
    "check_regular_file",
]

_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def project_root() -> Path:
    """The folder holding `codecs/`, `scenarios/` and `traces/`."""
    env = os.environ.get("UMA_HOME")
    return Path(env) if env else Path(__file__).resolve().parent.parent


def codecs_dir() -> Path:
    return project_root() / "codecs"


def scenarios_dir() -> Path:
    return project_root() / "scenarios"


def traces_dir() -> Path:
    return project_root() / "traces"


def shared_data_dir() -> Path:
    """`../shared/data` beside the clone (real traces and faces), or `UMA_SHARED_DATA`; may not exist."""
    env = os.environ.get("UMA_SHARED_DATA")
    return Path(env) if env else project_root().parent / "shared" / "data"


def _a(what: str) -> str:
    return f"{'an' if what[:1].lower() in 'aeiou' else 'a'} {what}"


def _mib(size_bytes: int) -> str:
    return f"{size_bytes / 2**20:g} MiB"


def check_regular_file(path: str | os.PathLike, *, error: type[Exception], what: str) -> int:
    """The size in bytes of regular file `path`; else `error` naming it in one line.

    A FIFO or device would block or never end, a symlink loop would raise `RuntimeError`
    deep in `pathlib`: each is refused here, as a missing file or a folder is. `what` names
    what was expected ("trace file").
    """
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise error(f"{path}: no such {what}") from None
    except OSError as err:
        if err.errno == errno.ELOOP:
            raise error(f"{path}: a symlink loop, expected {_a(what)}") from None
        raise error(f"{path}: cannot read ({err.strerror or err})") from None
    for test, kind in _KINDS:
        if test(info.st_mode):
            raise error(f"{path}: expected {_a(what)} (a regular file), got {kind}")
    return info.st_size


def read_capped(
    path: str | os.PathLike,
    *,
    max_bytes: int,
    error: type[Exception],
    what: str = "file",
    gunzip: bool = False,
) -> bytes:
    """The bytes of regular file `path`, refused with `error` when above `max_bytes`.

    With `gunzip`, a gzip file (by its magic) is decompressed, and `max_bytes` bounds what it
    expands to as well: a small file that would expand to gigabytes is refused while reading,
    never held whole. A truncated or corrupt gzip is `error` too.
    """
    size = check_regular_file(path, error=error, what=what)
    limit = f"above the maximum {_mib(max_bytes)} for {_a(what)}"
    if size > max_bytes:
        raise error(f"{path}: {size} bytes, {limit}")
    try:
        with open(path, "rb") as handle:
            data = handle.read(max_bytes + 1)
    except OSError as err:
        raise error(f"{path}: cannot read ({err.strerror or err})") from None
    if len(data) > max_bytes:
        raise error(f"{path}: more than {max_bytes} bytes, {limit}")
    if gunzip and data[:2] == b"\x1f\x8b":
        data = _gunzip_capped(data, max_bytes, path, what, error)
    return data


def _gunzip_capped(
    data: bytes, max_bytes: int, path: str | os.PathLike, what: str, error: type[Exception]
) -> bytes:
    """Decompress every gzip member of `data`, stopping as soon as more than `max_bytes` came."""
    import zlib

    out = bytearray()
    rest = data
    try:
        while rest:
            unzip = zlib.decompressobj(wbits=16 + zlib.MAX_WBITS)
            out += unzip.decompress(rest, max_bytes + 1 - len(out))
            if len(out) > max_bytes:
                raise error(
                    f"{path}: decompresses to more than {max_bytes} bytes, above the maximum "
                    f"{_mib(max_bytes)} for {_a(what)}"
                )
            if not unzip.eof:
                raise error(
                    f"{path}: a gzip-compressed {what} that does not decompress (truncated)"
                )
            rest = unzip.unused_data.lstrip(b"\0")  # members may follow, or padding
    except zlib.error as err:
        raise error(f"{path}: a gzip-compressed {what} that does not decompress ({err})") from None
    return bytes(out)
