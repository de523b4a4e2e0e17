"""A synthetic source's frames, rendered once per process and replayed to the runs after.

Units: bytes. The talking head and the pattern are functions of their settings and the seed, and
rendering the talking head (its noise above all) costs more than the codecs at CIF; the headline
runs six engines on one source in each worker process. `KeptSource` stands for the source
(every attribute but `frames` is the source's own), and its `frames()` yields copies of what the
process's first run rendered, rendering on where that run stopped. Past `KEEP_BYTES` nothing
more is kept: the run at the front renders on alone, and a run that falls behind it renders the
rest from a fresh source of its own. Only the newest settings' frames are kept.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator

import numpy as np

__all__ = ["KeptSource", "KEEP_BYTES"]

# 3,000 CIF frames (the default commute at 25 frames/s) are 456 MB.
KEEP_BYTES = 640 * 1024 * 1024


class _Kept:
    """The frames kept of one source, and its iterator, `position` frames in."""

    def __init__(self, source) -> None:
        self.frames: list[np.ndarray] = []
        self.kept_bytes = 0
        self.position = 0
        self.ended = False
        self.lock = threading.Lock()
        self._iterator = source.frames()

    def frame(self, index: int) -> np.ndarray | None | bool:
        """Frame `index`; None when the source ended there; False when it is neither kept
        nor the iterator's next (the caller renders it from a source of its own)."""
        if index < len(self.frames):
            return self.frames[index]
        if index != self.position:
            return False
        if self.ended:
            return None
        frame = next(self._iterator, None)
        if frame is None:
            self.ended = True
            return None
        if self.position == len(self.frames) and self.kept_bytes + frame.nbytes <= KEEP_BYTES:
            self.frames.append(frame)
            self.kept_bytes += frame.nbytes
        self.position += 1
        return frame


_KEPT: dict[str, _Kept] = {}
_KEPT_LOCK = threading.Lock()


class KeptSource:
    """`source`, whose frames are rendered once per process for the settings `key` names;
    `make` makes another such source (for a run that falls behind the kept frames)."""

    def __init__(self, source, key: str, make: Callable[[], object]) -> None:
        self._source = source
        self._key = key
        self._make = make

    def __getattr__(self, name: str):
        return getattr(self._source, name)

    def frames(self) -> Iterator[np.ndarray]:
        with _KEPT_LOCK:
            kept = _KEPT.get(self._key)
            if kept is None:
                _KEPT.clear()
                kept = _KEPT[self._key] = _Kept(self._source)
        index = 0
        while True:
            with kept.lock:
                frame = kept.frame(index)
            if frame is None:
                return
            if frame is False:
                break
            yield frame.copy()
            index += 1
        rest = self._make().frames()
        for _ in range(index):
            if next(rest, None) is None:
                return
        yield from rest
