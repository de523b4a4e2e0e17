"""The person's cut on a reference, kept by content: `uma.mbc.layers.cut_person` reads geometry
only, never the picture, so the second cut of the same scene points is the first's. One end
owns it (`uma.mbc.scene_memos.SceneMemos`, held by its renderers); the engine's mirror and the
receiver never share one.

Units: pixels; masks (H, W) uint8 0/1, as `cut_person` returns them.

The key is the SHA-256 of the scene's triangles and outline, the model's vertex and triangle
counts, the points' float64 bytes with their shape, the picture size and the halo (a content
address, as `uma.mbc.fill_memo`'s). The masks are kept bit-packed (13 kB each at CIF) and
every hit unpacks fresh arrays (a caller may write into them). Bounded: the newest
`CUT_ENTRIES` cuts.
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from collections.abc import Callable

import numpy as np

__all__ = ["CUT_ENTRIES", "CutMemo"]

CUT_ENTRIES = 64  # three packed CIF masks are 38 kB: 2.4 MB at most


def _key(scene, points: np.ndarray, size: tuple[int, int], halo_of_head: float) -> bytes:
    """The inputs' content address: what `cut_person` reads of them."""
    triangles = np.ascontiguousarray(scene.triangles)
    outline = np.ascontiguousarray(scene.outline)
    points = np.ascontiguousarray(points, dtype=np.float64)
    head = (
        f"{triangles.shape}{triangles.dtype}{outline.shape}{outline.dtype}{points.shape}"
        f"{scene.model.n_vertices},{len(scene.model.triangles)},{tuple(size)},{halo_of_head!r}"
    )
    digest = hashlib.sha256(head.encode())
    for array in (triangles, outline, points):
        digest.update(array.data)
    return digest.digest()


class CutMemo:
    """`cut(scene, points, size, halo_of_head)` is `cut_person(...)` of the same arguments,
    computed once for the same inputs among the newest `entries`."""

    def __init__(self, cut_person: Callable, entries: int = CUT_ENTRIES) -> None:
        self._cut, self.entries = cut_person, int(entries)
        self._kept: OrderedDict[bytes, tuple] = OrderedDict()
        self.hits = 0

    def cut(self, scene, points: np.ndarray, size: tuple[int, int], halo_of_head: float):
        """(head, halo, torso, anchor) as `cut_person` returns them, fresh arrays each call."""
        key = _key(scene, points, size, halo_of_head)
        kept = self._kept.get(key)
        if kept is not None:
            self._kept.move_to_end(key)
            self.hits += 1
            shape, packed, anchor = kept
            count = shape[0] * shape[1]
            masks = (np.unpackbits(p, count=count).reshape(shape) for p in packed)
            return (*masks, anchor.copy())
        *masks, anchor = self._cut(scene, points, size, halo_of_head)
        if not all(m.dtype == np.uint8 and m.shape == masks[0].shape and int(m.max(initial=0)) <= 1
                   for m in masks):  # fmt: skip
            return (*masks, anchor)  # not 0/1 uint8 masks of one shape: never kept
        packed = tuple(np.packbits(m) for m in masks)
        self._kept[key] = (masks[0].shape, packed, np.array(anchor, copy=True))
        while len(self._kept) > self.entries:
            self._kept.popitem(last=False)
        return (*masks, anchor)
