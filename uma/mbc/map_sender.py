"""The engine's side of the block map in a parameter stream: each decoded set drawn as the
receiver will, the frame's changes chosen against the source, the map's allowance fed by the
parameters' own bits as their packets close.

Units: pictures planar YUV 4:2:0 (H * 3 // 2, W) uint8; bits.

The map's drawing is the engine's one drawing of its mirror a frame: on a frame whose set the
refresh's judge reads too (`uma.mbc.refresh_gain_db`, and the mirror's take of that refresh a
few frames later), the caller asks for it `whole`; the mirror then draws its whole luma once
and keeps it (`uma.mbc.render_memo`), and the judge and the take are handed that picture
instead of drawing the same set again. The choice reads only its window, whose luma a whole
drawing holds to the bit, so the map's changes are the same either way.
"""

from __future__ import annotations

import numpy as np

from uma.mbc.block_map import BlockMap
from uma.mbc.errors import SceneError

__all__ = ["MapSender"]


class MapSender:
    """The block map of a stream of pictures of `size` (W, H) at `fps`, at the engine."""

    def __init__(self, size: tuple[int, int], fps: float):
        self.block_map = BlockMap(size, fps)
        # The parameters' own bits a frame (the last packet's, less its map's): the map spends
        # what its allowance leaves; nothing before the first packet closed.
        self.stream_bits = self.block_map.frame_bits
        self._map_bits_open = 0

    @property
    def map_blocks(self) -> int:
        return self.block_map.map_blocks

    def changes(self, mirror, units, decoded: np.ndarray, source: np.ndarray, *, whole=False):
        """The frame's changes ((n, 2)) for the decoded set `decoded` (`units`' values) drawn
        by `mirror` (the receiver's renderer as the engine mirrors it) against the source
        luma `source`; None when the mirror cannot draw the set (the receiver keeps its last
        picture). Nothing is drawn while the map holds no choice and cannot pay for one.
        `whole`: the mirror draws its whole luma and keeps it for the frame's other readers
        (the refresh's judge and take); else only the window the choice reads."""
        before = self.block_map.bits
        if self.block_map.idle(self.stream_bits):
            self._map_bits_open += self.block_map.bits - before
            return self.block_map.sent
        params, light = units.split(decoded)
        body = units.body_of(decoded)
        bits = self.block_map.bits
        if self.block_map.broke(self.stream_bits):  # nothing to choose: the face alone
            try:
                face = mirror.face_mask(params, light, body)
            except SceneError:
                return None
            self.block_map.hold_with(mirror, face, self.stream_bits)
            self._map_bits_open += self.block_map.bits - bits
            return self.block_map.sent
        # The choice reads luma only, and only its window's (and its blurs' margin): the mirror
        # draws no chroma and, unless another reader wants the picture, only about that box;
        # nothing is composed.
        only = None if whole else self.block_map.read_box
        try:
            shown, face = mirror.render(params, light, body, luma_only=True, only=only)
        except SceneError:
            return None
        self.block_map.step_with(mirror, shown, face, source, self.stream_bits, compose=False)
        self._map_bits_open += self.block_map.bits - bits
        return self.block_map.sent

    def count(self, packets) -> None:
        """The parameters' own bits a frame from the packets just closed."""
        for packet in packets:
            own = packet.size_bytes * 8 - self._map_bits_open
            self.stream_bits = max(own, 0) / packet.count
            self._map_bits_open = 0
