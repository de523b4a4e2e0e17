"""What one end's renderers keep by content: the person's cuts and the plate's luma fills.

Units: as `uma.mbc.cut_memo` and `uma.mbc.fill_memo` (pixels; masks and planes at the
picture's size).

Each end owns its memos: a `uma.mbc.scene_render.SceneRenderer` builds its own unless it is
handed one (an end with several renderers may share one among them). Nothing is shared through
module state, so the engine's mirror and the receiver each pay their own cut and fill of a
refresh, in one process as on two devices.
"""

from __future__ import annotations

from uma.mbc.cut_memo import CUT_ENTRIES, CutMemo
from uma.mbc.fill_memo import MEMO_ENTRIES, FillMemo

__all__ = ["SceneMemos"]


class SceneMemos:
    """One end's memos: `cuts` (`cut_person` by content) and `fills` (the plate's luma
    `fill_unknown` by content), each holding the newest `cut_entries` / `fill_entries`."""

    def __init__(self, cut_entries: int = CUT_ENTRIES, fill_entries: int = MEMO_ENTRIES) -> None:
        from uma.mbc.layers import cut_person, fill_unknown

        self.cuts = CutMemo(cut_person, cut_entries)
        self.fills = FillMemo(fill_unknown, fill_entries)
