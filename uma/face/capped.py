"""Reading a whole face-room input file, up to a stated size, with one-line `FaceError`s.

Every face-room reader starts here: `uma.paths.read_capped` (regular files only, so a FIFO or
a device never blocks a read; a missing file, a folder, a symlink loop and a file larger than
its kind can be are each one line) with the face room's error.
"""

from __future__ import annotations

from pathlib import Path

from uma.errors import FaceError

__all__ = ["read_capped"]


def read_capped(path: str | Path, *, what: str, limit: int) -> bytes:
    """The bytes of `path` (a `what`, for messages), refused beyond `limit` bytes."""
    from uma import paths

    return paths.read_capped(path, max_bytes=limit, error=FaceError, what=what)
