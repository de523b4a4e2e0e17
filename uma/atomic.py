"""Whole-or-nothing writing: a reader sees the old result whole or the new one whole, never a mix.

One file: write a temporary file in the same folder, fsync, then `os.replace` it over the target
(atomic on POSIX). A crash leaves the old file, or none, plus at most a stray `.tmp`.

A folder of files (one run's results, a sweep point): `atomic_dir` builds the whole folder as a
hidden sibling, fsyncs it, then swaps it in. On Linux the swap is one `renameat2(RENAME_EXCHANGE)`
call, so there is no moment without a folder; elsewhere (or on a file system without it) the
old folder is renamed aside and the new one renamed in, and between those two renames the
folder is absent (never mixed). A crash leaves at most a hidden sibling
`.NAME.uma-PID@HOST-*.tmp`, which the next write of NAME on HOST removes once PID has ended
(temporary files of single files are named and cleared alike).

Several files in a shared folder (a sweep's CSV and Parquet tables): `atomic_files` writes every
temporary file first and replaces them in the order given; only a crash between two `os.replace`
calls (no data is written there) leaves the earlier files new and the later ones old.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import shutil
import sys
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import IO

__all__ = [
    "atomic_write_bytes",
    "atomic_write_text",
    "atomic_open",
    "atomic_dir",
    "atomic_files",
    "check_replaceable",
    "prepare_out_dir",
]


def prepare_out_dir(
    path: str | os.PathLike,
    *,
    what: str = "--out",
    replaceable: Sequence[str] | None = None,
) -> Path:
    """Check now, before any work, that results can be written into folder `path`.

    Raises `OutputError` naming it when a file stands where the folder (or one of its parents)
    should be or the place is not writable, so a run fails at once rather than after minutes
    of simulation. Nothing is created: bad input leaves no empty folder behind. With
    `replaceable` (name patterns, see `check_replaceable`) the folder is one `atomic_dir` swaps
    whole: it must hold only such names, and its parent must be writable.
    """
    from uma.errors import OutputError

    if not str(path).strip():
        raise OutputError(f"{what}: expected a folder name, got {str(path)!r}")
    out = Path(path)
    longest = max((len(os.fsencode(part)) for part in out.parts), default=0)
    if longest > 255 or len(os.fsencode(str(out))) > 4000:
        shown = str(out) if len(str(out)) <= 60 else str(out)[:57] + "..."
        raise OutputError(
            f"{what}: expected a path the file system can hold (names of at most 255 bytes), "
            f"got {shown!r} (a name of {longest} bytes)"
        )
    existing = out if replaceable is None else out.parent
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if out.exists() and not out.is_dir():
        existing = out
    if not existing.is_dir():
        raise OutputError(
            f"{what}: expected a folder for the results, got an existing file {str(existing)!r}"
        )
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OutputError(f"{what}: cannot write into {str(existing)!r} (permission denied)")
    if replaceable is not None:
        check_replaceable(out, replaceable, what=what)
        # The staging folder beside it is `.NAME.uma-PID@HOST-RANDOM.tmp.old` at worst.
        most = 255 - len(os.fsencode(_prefix(""))) - len("12345678.tmp.old")
        if len(os.fsencode(out.name)) > most:
            raise OutputError(
                f"{what}: expected a folder name of at most {most} bytes (uma stages the "
                f"results beside it under a longer name), got {len(os.fsencode(out.name))}"
            )
    return out


def check_replaceable(
    path: str | os.PathLike,
    patterns: Sequence[str],
    *,
    what: str = "--out",
    folders: Sequence[str] = (),
) -> None:
    """Raise `OutputError` unless folder `path` is absent, empty or holds only what uma wrote:
    regular files matching `patterns`, sub-folders named in `folders`, uma's temporaries.

    Swapping a folder whole deletes what it held: this keeps `--out ~` from deleting a home,
    and a user's `notes.tmp` or folder `timeline-notes.png/` from going with an old run.
    """
    from uma.errors import OutputError

    folder = Path(os.path.realpath(path))
    try:
        here = Path.cwd().resolve()
    except OSError:  # the current folder was deleted: nothing to protect
        here = None
    if here is not None and (folder == here or folder in here.parents):
        raise OutputError(
            f"{what}: expected a results folder other than the current folder or one "
            f"holding it, got {str(path)!r}"
        )
    if not folder.exists():
        return
    if not folder.is_dir():
        raise OutputError(
            f"{what}: expected a folder for the results, got an existing file {str(folder)!r}"
        )
    try:
        entries = sorted(os.scandir(folder), key=lambda entry: entry.name)
    except OSError as err:
        raise OutputError(f"{what}: cannot read {str(folder)!r} ({err.strerror or err})") from None
    foreign = [entry.name for entry in entries if not _is_ours(entry, patterns, folders)]
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise OutputError(
            f"{what}: {str(folder)!r} holds files that are not results ({shown}); expected an "
            f"empty folder or one written by uma, so replacing it loses nothing else"
        )


# What uma's own temporaries are named (`_prefix`): `.NAME.uma-PID@HOST-RANDOM.tmp`.
_UMA_TEMPORARY = re.compile(r"^\..+\.uma-[0-9]+@[^/]*-[^/]+\.tmp(\.old)?$")


def _is_ours(entry: os.DirEntry, patterns: Sequence[str], folders: Sequence[str] = ()) -> bool:
    """Whether uma may have written `entry`: one of its temporaries (by name), or a regular
    file (not a folder, not a link) matching a pattern. A pattern for temporaries
    (`.*.tmp`) matches only names uma gives them, so a user's `.precious.tmp` is kept."""
    from fnmatch import fnmatchcase

    if _UMA_TEMPORARY.match(entry.name):
        return True
    try:
        if entry.name in folders:
            return entry.is_dir(follow_symlinks=False)
        plain_file = entry.is_file(follow_symlinks=False)
    except OSError:
        return False
    return plain_file and any(
        fnmatchcase(entry.name, p) for p in patterns if not p.endswith(".tmp")
    )


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """Open a temporary file beside `path`; on clean exit it replaces `path`, on error it vanishes."""
    from uma.errors import OutputError

    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        _remove_stale(target.parent, target.name)
        fd, tmp = tempfile.mkstemp(prefix=_prefix(target.name), suffix=".tmp", dir=target.parent)
    except OSError as err:
        raise OutputError(f"{target}: cannot write ({err.strerror or err})") from None
    try:
        _chmod_plain(tmp)
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


# Steps of the folder swap, module-level so that tests can fail or kill each one.
_RENAME_EXCHANGE = 2  # linux/fs.h
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap `a` and `b` in one `renameat2` call; False where the system cannot."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = [
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_uint,
    ]
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EXDEV):
        return False  # this file system cannot exchange: rename aside instead
    raise OSError(code, os.strerror(code), str(b))


def _fsync_tree(folder: Path) -> None:
    """Flush every file below `folder`, then the folders themselves, to the disk."""
    for root, _dirs, files in os.walk(folder):
        for name in files:
            fd = os.open(os.path.join(root, name), os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
        _fsync_dir(Path(root))


def _fsync_dir(folder: Path) -> None:
    with contextlib.suppress(OSError):  # some file systems cannot fsync a folder
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _swap_in(staging: Path, target: Path) -> Path | None:
    """Put `staging` at `target`; returns where the old folder now is (to delete), or None."""
    if not target.exists():
        try:
            os.rename(staging, target)  # replaces an empty folder too
            return None
        except OSError as err:
            if err.errno not in (errno.ENOTEMPTY, errno.EEXIST):
                raise  # else another writer made it meanwhile: swap with theirs
    if _exchange(staging, target):
        return staging
    aside = Path(f"{staging}.old")
    os.rename(target, aside)
    try:
        os.rename(staging, target)
    except BaseException:
        os.rename(aside, target)  # put the old folder back: absent is worse than old
        raise
    return aside


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _prefix(name: str) -> str:
    """Temporary names say who writes them, so that only an ended writer's leftovers are removed."""
    import socket

    return f".{name}.uma-{os.getpid()}@{socket.gethostname()}-"


def _remove_stale(folder: Path, name: str) -> None:
    """Delete what an ended writer of `name` on this host left in `folder` (killed mid-write).

    A writer on another host sharing the folder (a Dask worker) may still be alive: its
    leftovers are kept.
    """
    import socket

    prefix = f".{name}.uma-"
    with contextlib.suppress(OSError):
        for entry in os.scandir(folder):
            if not entry.name.startswith(prefix) or "-" not in entry.name[len(prefix) :]:
                continue
            owner = entry.name[len(prefix) :].rsplit("-", 1)[0]
            pid, _, host = owner.partition("@")
            if host != socket.gethostname() or not pid.isdigit() or int(pid) == os.getpid():
                continue
            if not _pid_alive(int(pid)):
                if entry.is_dir(follow_symlinks=False):
                    shutil.rmtree(entry.path, ignore_errors=True)
                else:
                    with contextlib.suppress(OSError):
                        os.unlink(entry.path)


@contextlib.contextmanager
def atomic_dir(
    path: str | os.PathLike, *, replaceable: Sequence[str] = ("*",), what: str = "--out"
) -> Iterator[Path]:
    """Yield an empty hidden folder beside `path`; on clean exit it becomes `path`, whole.

    Write every file of the result into the yielded folder. On an error (or a kill) inside the
    block, `path` keeps what it held, whole, and the temporary folder is removed. `replaceable`
    is what `check_replaceable` allows `path` to hold. A symlink at `path` is followed: the
    folder it points to is replaced.
    """
    from uma.errors import OutputError

    target = Path(os.path.realpath(path))  # a symlink's folder is replaced, not the link
    check_replaceable(target, replaceable, what=what)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        _remove_stale(target.parent, target.name)
        staging = Path(
            tempfile.mkdtemp(prefix=_prefix(target.name), suffix=".tmp", dir=target.parent)
        )
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(staging, 0o777 & ~umask)
    except OSError as err:
        raise OutputError(f"{target}: cannot write ({err.strerror or err})") from None
    old: Path | None = None
    try:
        yield staging
        _fsync_tree(staging)
        old = _swap_in(staging, target)
        _fsync_dir(target.parent)
    except BaseException as err:
        if old is None:
            shutil.rmtree(staging, ignore_errors=True)
        if isinstance(err, OSError) and not isinstance(err, OutputError):
            raise OutputError(f"{target}: cannot write ({err.strerror or err})") from None
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def atomic_files(folder: str | os.PathLike, files: Mapping[str, bytes]) -> None:
    """Write `files` (name -> bytes) into `folder`: every temporary first, then replace in order.

    Put the file readers treat as the index last: it never names more than the others hold.
    """
    from uma.errors import OutputError

    out = Path(folder)
    temps: list[tuple[str, Path]] = []
    try:
        out.mkdir(parents=True, exist_ok=True)
        for name, data in files.items():
            _remove_stale(out, name)
            fd, tmp = tempfile.mkstemp(prefix=_prefix(name), suffix=".tmp", dir=out)
            temps.append((name, Path(tmp)))
            _chmod_plain(tmp)
            with os.fdopen(fd, "wb") as handle:
                handle.write(data)
                handle.flush()
                os.fsync(handle.fileno())
        for name, tmp in temps:
            os.replace(tmp, out / name)
        _fsync_dir(out)
    except BaseException as err:
        for _name, tmp in temps:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)
        if isinstance(err, OSError) and not isinstance(err, OutputError):
            raise OutputError(f"{out}: cannot write ({err.strerror or err})") from None
        raise


def _chmod_plain(path: str | os.PathLike) -> None:
    """mkstemp makes the file private; give it the permissions an ordinary file would get."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, 0o666 & ~umask)
