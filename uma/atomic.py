"""Atomic file writing: a reader never sees a half-written result.

Write to a temporary file in the same folder, flush and fsync, then `os.replace` it over the
target (atomic on POSIX). A crash leaves the old file, or none, plus at most a stray `.tmp`.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO

__all__ = ["atomic_write_bytes", "atomic_write_text", "atomic_open", "prepare_out_dir"]


def prepare_out_dir(path: str | os.PathLike, *, what: str = "--out") -> Path:
    """Check now, before any work, that results can be written into folder `path`.

    Raises `OutputError` naming it when a file stands where the folder (or one of its parents)
    should be or the place is not writable, so a run fails at once rather than after minutes
    of simulation. Nothing is created: bad input leaves no empty folder behind.
    """
    from uma.errors import OutputError

    out = Path(path)
    existing = out
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise OutputError(
            f"{what}: expected a folder for the results, got an existing file {str(existing)!r}"
        )
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OutputError(f"{what}: cannot write into {str(existing)!r} (permission denied)")
    return out


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """Open a temporary file beside `path`; on clean exit it replaces `path`, on error it vanishes."""
    from uma.errors import OutputError

    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    except OSError as err:
        raise OutputError(f"{target}: cannot write ({err.strerror or err})") from None
    try:
        # mkstemp makes the file private; give it the permissions an ordinary file would get.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        with os.fdopen(fd, mode, **kwargs) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException as err:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        if isinstance(err, OSError) and not isinstance(err, OutputError):
            # Disk full, permission, a folder where the file goes: one line, not a traceback.
            raise OutputError(f"{target}: cannot write ({err.strerror or err})") from None
        raise


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write `data` to `path` atomically."""
    with atomic_open(path, "wb") as handle:
        handle.write(data)


def atomic_write_text(path: str | os.PathLike, text: str) -> None:
    """Write `text` (UTF-8, newline '\\n') to `path` atomically."""
    with atomic_open(path, "w", encoding="utf-8", newline="\n") as handle:
        handle.write(text)
