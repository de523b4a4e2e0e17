"""Reading a whole input file, up to a stated size, with one-line errors.

Every face-room reader starts here, so a missing file, a folder, an unreadable file and a file
far larger than its kind can be (or one without end, such as `/dev/zero`) read the same way:
`PATH: no such WHAT`, `PATH: expected a file (WHAT), got a folder`, `PATH: expected at most
N bytes (WHAT), got more`.
"""

from __future__ import annotations

from pathlib import Path

from uma.errors import FaceError

__all__ = ["read_capped"]


def read_capped(path: str | Path, *, what: str, limit: int) -> bytes:
    """The bytes of `path` (a `what`, for messages), refused beyond `limit` bytes."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            data = handle.read(limit + 1)
    except FileNotFoundError:
        raise FaceError(f"{path}: no such {what}") from None
    except IsADirectoryError:
        raise FaceError(f"{path}: expected a file ({what}), got a folder") from None
    except OSError as err:
        raise FaceError(f"{path}: cannot read ({err.strerror or err})") from None
    if len(data) > limit:
        raise FaceError(f"{path}: expected at most {limit} bytes ({what}), got more")
    return data
