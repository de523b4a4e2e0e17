"""The last few pictures a renderer drew at its current reference: a picture asked for again
(the same pose, light and body motion) is handed back instead of drawn again.

Units: none (keys are the inputs' float64 bytes); pictures as `uma.mbc.scene_render`'s.

A receiver draws a refresh's frame twice: once to show it, and again a few frames later to
paste the decoded box on when the refresh arrives (`uma.mbc.refresh_coder.take_refresh`);
while no other reference came in between, that second drawing is the first one. The owner
clears the memo whenever what it draws from changes (a new reference, another face source).
"""

from __future__ import annotations

import numpy as np

__all__ = ["RenderMemo", "MEMO_PICTURES"]

MEMO_PICTURES = 4  # the newest pictures kept (a refresh arrives a few frames after its own)


def _key(values) -> bytes | None:
    return None if values is None else np.asarray(values, dtype=np.float64).tobytes()


class RenderMemo:
    """Up to `MEMO_PICTURES` (picture, face mask) pairs by (params, light, body); each given
    out and taken in as a copy (a caller may draw on what it gets)."""

    def __init__(self) -> None:
        self._kept: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}
        self.hits = 0

    def clear(self) -> None:
        self._kept.clear()

    def get(self, params, light, body) -> tuple[np.ndarray, np.ndarray] | None:
        """A copy of what was drawn at these inputs since the last `clear`, or None."""
        kept = self._kept.get((_key(params), _key(light), _key(body)))
        if kept is None:
            return None
        self.hits += 1
        return kept[0].copy(), kept[1].copy()

    def put(self, params, light, body, picture: np.ndarray, face: np.ndarray) -> None:
        """Keep a copy of what was drawn at these inputs (the oldest goes past the limit)."""
        self._kept[(_key(params), _key(light), _key(body))] = (picture.copy(), face.copy())
        while len(self._kept) > MEMO_PICTURES:
            del self._kept[next(iter(self._kept))]
