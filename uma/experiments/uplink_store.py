"""The sender's uplink stream kept on disk, content-addressed, shared by runs and processes.

Units: sizes in bytes (`max_bytes`) or MiB (`UMA_CACHE_MB`); pictures are planar YUV 4:2:0
arrays (H * 3 // 2, W) uint8.

The sender's stream and the engine's decode of it are the same in every run of a given source
and sender setting (`uma.sim.uplink`). `UplinkStore` keeps each coded frame and its decoded
picture in one file named by the frame's address (`uma.sim.uplink.chain` over `settings_key`:
the uplink codec, the sender's settings, the picture size and rate, the PyAV/FFmpeg/NumPy
versions and every source frame's bytes so far), so sweep points, the headline's pairs and
`uma bench sim` in any process take what an earlier run computed. It answers as an
`UplinkMemo` does (`found`, `keep`, `keep_picture`, `pictures[key]`), so a run takes it as
`run_scenario(..., uplink=store)` and gives byte for byte what computing afresh gives
(`tests/experiments/test_uplink_store.py`).

- **Where**: `$UMA_CACHE/uplink-v1`, else `$XDG_CACHE_HOME/uma/uplink-v1`, else
  `~/.cache/uma/uplink-v1`; never a results folder (a sweep refuses a store inside its
  `--out`). `UMA_CACHE=off` turns it off.
- **How big**: `UMA_CACHE_MB` (default 4096); past it the files used longest ago go first (a
  file found is touched, so "oldest" is least recently used), down to 90 % of the bound.
- **Writes** are atomic: a temporary file in the same folder, then `os.replace`; two workers
  writing one frame write the same bytes, and the last rename wins. A file that cannot be read
  whole is a miss and is removed; a store that cannot write stops writing and the run goes on.
- **Pictures are kept raw**: zlib, the compressor at hand, costs more to undo (0.69 ms per CIF
  picture) than the H.264 decode it would save (0.36 ms); a raw read costs 0.03 ms
  (docs/benchmarks.md). The coded frame beside it is small (sender rate / frame rate).
"""

from __future__ import annotations

import contextlib
import os
import struct
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from uma.errors import ConfigError
from uma.sim.uplink import UplinkFrame

__all__ = ["StoreSettings", "store_settings", "UplinkStore", "evict", "open_store", "DEFAULT_MB"]

DEFAULT_MB = 4096
FOLDER = "uplink-v1"  # a new layout is a new folder
_OFF = {"off", "0", "no", "false", "none"}
_MAGIC = b"UMAUPL1\n"
_HEADER = struct.Struct("<8sqBIii")  # magic, pts, keyframe, data bytes, picture height, width


@dataclass(frozen=True)
class StoreSettings:
    """Where the store lives and how big it may grow; plain data that travels to a worker."""

    root: Path
    max_bytes: int

    def task(self) -> dict:
        return {"root": str(self.root), "max_bytes": self.max_bytes}

    @classmethod
    def from_task(cls, data: dict | None) -> StoreSettings | None:
        return None if data is None else cls(Path(data["root"]), int(data["max_bytes"]))


def store_settings(environ: Mapping[str, str] | None = None) -> StoreSettings | None:
    """The store the environment asks for (None: `UMA_CACHE=off`); `ConfigError` naming the
    variable on a bad size."""
    env = os.environ if environ is None else environ
    where = env.get("UMA_CACHE", "").strip()
    if where.lower() in _OFF:
        return None
    if where:
        base = Path(where).expanduser()
    else:
        base = Path(env.get("XDG_CACHE_HOME") or Path.home() / ".cache").expanduser() / "uma"
    text = env.get("UMA_CACHE_MB", str(DEFAULT_MB)).strip()
    try:
        size_mb = float(text)
    except ValueError:
        size_mb = float("nan")
    if not 1 <= size_mb < 2**40:
        raise ConfigError(f"UMA_CACHE_MB: expected a size in MiB of at least 1, got {text!r}")
    return StoreSettings(base / FOLDER, int(size_mb * 2**20))


def open_store(data: dict | None, *, in_memory: bool = False) -> UplinkStore | None:
    """The store a task names (`StoreSettings.task()`), or None when it names none."""
    settings = StoreSettings.from_task(data)
    return None if settings is None else UplinkStore(settings, in_memory=in_memory)


class _TakenOnce(dict):
    """Pictures read from disk, each handed out once (`pictures[key]` removes it)."""

    def __getitem__(self, key: bytes) -> np.ndarray | None:
        return self.pop(key)


class UplinkStore:
    """Coded frames and decoded pictures by address, on disk (see the module's docstring).

    `in_memory=True` also keeps every frame and picture in this process (a run and its replay
    in `uma bench sim`); otherwise a picture found is held only until the engine takes it.
    `hits`, `misses`, `written` count frames.
    """

    def __init__(self, settings: StoreSettings, *, in_memory: bool = False) -> None:
        self.settings, self.in_memory = settings, in_memory
        self.frames: dict[bytes, UplinkFrame] = {}  # in memory; or coded, awaiting its picture
        self.pictures: dict[bytes, np.ndarray | None] = {} if in_memory else _TakenOnce()
        self.hits = self.misses = self.written = 0
        self._stored_bytes: int | None = None  # the folder's size, once measured
        self._writable = True

    def _path(self, key: bytes) -> Path:
        name = key.hex()
        return self.settings.root / name[:2] / f"{name}.bin"

    def found(self, key: bytes) -> UplinkFrame | None:
        if self.in_memory and key in self.frames and key in self.pictures:
            self.hits += 1
            return self.frames[key]
        loaded = self._read(key)
        if loaded is None:
            self.misses += 1
            return None
        frame, picture = loaded
        self.hits += 1
        self.pictures[key] = picture
        if self.in_memory:
            self.frames[key] = frame
        return frame

    def keep(self, frame: UplinkFrame) -> None:
        self.frames[frame.key] = replace(frame, taken=False, catch_up=())

    def keep_picture(self, key: bytes, picture: np.ndarray | None) -> None:
        frame = self.frames.get(key) if self.in_memory else self.frames.pop(key, None)
        if self.in_memory:
            self.pictures[key] = picture
        if frame is not None and self._writable:
            self._write(frame, picture)

    def _read(self, key: bytes) -> tuple[UplinkFrame, np.ndarray | None] | None:
        path = self._path(key)
        try:
            with open(path, "rb") as file:
                data = file.read()
        except OSError:
            return None
        parsed = _parse(data, key)
        with contextlib.suppress(OSError):
            if parsed is None:
                path.unlink()  # damaged (renames are atomic): the next writer replaces it
            else:
                os.utime(path)  # used now: the last to be evicted
        return parsed

    def _write(self, frame: UplinkFrame, picture: np.ndarray | None) -> None:
        blob = _pack(frame, picture)
        path = self._path(frame.key)
        if blob is None:
            return
        temporary = path.parent / f".{path.name}.{os.getpid()}.{id(self):x}.tmp"
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            with open(temporary, "wb") as file:
                file.write(blob)
            os.replace(temporary, path)
        except OSError:
            self._writable = False  # a full or read-only disk: the run goes on without it
            with contextlib.suppress(OSError):
                temporary.unlink()
            return
        self.written += 1
        if self._stored_bytes is None:
            self._stored_bytes = _folder_bytes(self.settings.root)
        else:
            self._stored_bytes += len(blob)
        if self._stored_bytes > self.settings.max_bytes:
            self._stored_bytes = evict(self.settings.root, int(0.9 * self.settings.max_bytes))


def _pack(frame: UplinkFrame, picture: np.ndarray | None) -> bytes | None:
    """One frame's file; None for a picture this layout cannot hold (not 2-D uint8)."""
    if picture is None:
        shape = (-1, -1)
        pixels = b""
    elif picture.dtype == np.uint8 and picture.ndim == 2:
        shape = picture.shape
        pixels = np.ascontiguousarray(picture).tobytes()
    else:
        return None
    head = _HEADER.pack(_MAGIC, frame.pts, frame.is_keyframe, len(frame.data), *shape)
    return head + frame.data + pixels


def _parse(blob: bytes, key: bytes) -> tuple[UplinkFrame, np.ndarray | None] | None:
    """A frame's file read back; None when it is not one whole (a miss)."""
    if len(blob) < _HEADER.size:
        return None
    magic, pts, keyframe, size, height, width = _HEADER.unpack_from(blob)
    pixels = max(height, 0) * max(width, 0)
    if magic != _MAGIC or len(blob) != _HEADER.size + size + pixels:
        return None
    start = _HEADER.size + size
    frame = UplinkFrame(blob[_HEADER.size : start], pts, bool(keyframe), key)
    if height < 0:
        return frame, None
    picture = np.frombuffer(bytearray(blob[start:]), dtype=np.uint8).reshape(height, width)
    return frame, picture


def _files(root: Path) -> list[os.DirEntry]:
    entries = []
    try:
        folders = list(os.scandir(root))
    except OSError:
        return entries
    for folder in folders:
        if folder.is_dir(follow_symlinks=False):
            try:
                entries += [e for e in os.scandir(folder.path) if e.is_file(follow_symlinks=False)]
            except OSError:
                continue
    return entries


def _folder_bytes(root: Path) -> int:
    total = 0
    for entry in _files(root):
        try:
            total += entry.stat(follow_symlinks=False).st_size
        except OSError:
            continue
    return total


def evict(root: Path, keep_bytes: int) -> int:
    """Remove the files of `root` used longest ago until at most `keep_bytes` remain (another
    process may remove some first); the bytes that remain."""
    sized = []
    for entry in _files(root):
        try:
            stat = entry.stat(follow_symlinks=False)
        except OSError:
            continue
        sized.append((stat.st_mtime_ns, stat.st_size, entry.path))
    sized.sort()
    total = sum(size for _, size, _ in sized)
    for _, size, path in sized:
        if total <= keep_bytes:
            break
        try:
            os.unlink(path)
        except FileNotFoundError:
            pass
        except OSError:
            continue
        total -= size
    return total
