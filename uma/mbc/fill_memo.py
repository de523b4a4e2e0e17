"""The plate's luma fill, kept by content: the second fill of the same luma over the same known
mask is the first's. One end owns it (`uma.mbc.scene_memos.SceneMemos`, held by its
renderers); the engine's mirror and the receiver never share one.

Units: pixels; a plane (H, W) uint8, its known mask (H, W) bool.

The key is the SHA-256 of the plane's and the mask's bytes with their shape and the edge rule
(a content address, as the uplink memo's); a kept fill is read-only and the same array for
every hit (the plate copies it into its picture). Bounded: the newest `MEMO_ENTRIES` fills.
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from collections.abc import Callable

import numpy as np

__all__ = ["MEMO_ENTRIES", "FillMemo"]

MEMO_ENTRIES = 64  # a CIF luma fill is 101 kB: 6.5 MB at most


def _key(plane: np.ndarray, known: np.ndarray, edge: str | None) -> bytes:
    """The inputs' content address: shapes, types, edge rule and bytes."""
    digest = hashlib.sha256(f"{plane.shape}{plane.dtype}{known.dtype}{edge}".encode())
    digest.update(np.ascontiguousarray(plane).data)
    digest.update(np.ascontiguousarray(known).data)
    return digest.digest()


class FillMemo:
    """`fill(plane, known, edge)` is `fill_unknown(plane, known, edge)`, computed once for
    the same inputs among the newest `entries`."""

    def __init__(
        self,
        fill_unknown: Callable[[np.ndarray, np.ndarray, str | None], np.ndarray],
        entries: int = MEMO_ENTRIES,
    ) -> None:
        self._fill, self.entries = fill_unknown, int(entries)
        self._kept: OrderedDict[bytes, np.ndarray] = OrderedDict()
        self.hits = 0

    def fill(self, plane: np.ndarray, known: np.ndarray, edge: str | None = None) -> np.ndarray:
        """The filled plane (read-only; never write into it)."""
        key = _key(plane, known, edge)
        kept = self._kept.get(key)
        if kept is not None:
            self._kept.move_to_end(key)
            self.hits += 1
            return kept
        out = self._fill(plane, known, edge)
        out.flags.writeable = False
        self._kept[key] = out
        while len(self._kept) > self.entries:
            self._kept.popitem(last=False)
        return out
