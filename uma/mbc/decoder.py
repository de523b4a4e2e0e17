"""The receiving side: packets to parameters (`ParameterDecoder`), parameters to pictures
(`FaceRenderer`).

Units: parameters as in `uma.face.geometry`; pictures are gray (luma) uint8 at the source size.

The decoder takes packets in arrival order. A packet that is not one (truncated, checksum
mismatch, foreign version, a stream that does not decode) raises `PacketError`; a valid packet
out of turn is reported as an event and changes nothing: a duplicate or a late (reordered)
packet is dropped; a gap in the sequence numbers (missing packets) loses the reference, and
the decoder waits (`needs_intra`: the receiver should ask for an intra set) until the next
intra packet, where it resynchronises. The last decoded parameters stay on screen meanwhile
(`params`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.face.describe import ContentDescription
from uma.mbc.coding import AdaptiveModels, decode_sets
from uma.mbc.errors import PacketError
from uma.mbc.packets import FRAME_MODULUS, SEQ_MODULUS, parse_packet
from uma.mbc.quant import Quantiser
from uma.mbc.stream import StreamConfig
from uma.mbc.units import FaceUnits

__all__ = ["DecodeEvent", "Decoded", "ParameterDecoder", "FaceRenderer", "EVENT_KINDS"]

EVENT_KINDS = ("resync", "missing", "duplicate", "late", "waiting", "bad_packet")


@dataclass(frozen=True)
class DecodeEvent:
    """Something the receiver should know: `kind` is one of EVENT_KINDS."""

    kind: str
    seq: int
    detail: str = ""


@dataclass(frozen=True, eq=False)
class Decoded:
    """What one packet gave: (frame index, parameters) for each decoded frame, and events."""

    frames: tuple[tuple[int, np.ndarray], ...]
    events: tuple[DecodeEvent, ...]
    changes: tuple[np.ndarray, ...] = ()  # each frame's block map changes (a map stream)


class ParameterDecoder:
    """Mirror of `uma.mbc.stream.ParameterEncoder` with the same units and configuration."""

    def __init__(self, units: FaceUnits, config: StreamConfig = StreamConfig(), map_blocks=0):
        self.units = units
        self.config = config
        self.map_blocks = int(map_blocks)  # the block map's window (0: the stream has none)
        self.quantiser = Quantiser(units.kinds, config.quantiser)
        self.models = AdaptiveModels(units.unit.size, config.coder)
        self._expected_seq: int | None = None
        self._next_frame: int | None = None
        self._reference: np.ndarray | None = None  # face animation units
        self.params: np.ndarray | None = None  # on screen: the last decoded parameters
        self.packets = 0

    @property
    def needs_intra(self) -> bool:
        return self._reference is None

    def _lose_sync(self) -> None:
        self._reference = None

    def decode(self, data: bytes) -> Decoded:
        """Decode one packet; see the module's docstring for what happens to bad ones."""
        where = f"MBC packet {self.packets}"
        self.packets += 1
        packet = parse_packet(data, where=where)
        events: list[DecodeEvent] = []
        if self._expected_seq is not None:
            ahead = (packet.seq - self._expected_seq) % SEQ_MODULUS
            if ahead >= SEQ_MODULUS // 2:
                behind = SEQ_MODULUS - ahead
                kind = "duplicate" if behind == 1 else "late"
                return Decoded((), (DecodeEvent(kind, packet.seq, f"{behind} behind"),))
            if ahead:
                events.append(DecodeEvent("missing", packet.seq, f"{ahead} packet(s) lost"))
                self._lose_sync()
        self._check_layout(packet, where)
        self._expected_seq = (packet.seq + 1) % SEQ_MODULUS
        if not packet.intra:
            if self._reference is not None and packet.first_frame != self._next_frame:
                detail = f"frame {packet.first_frame} follows {self._next_frame}"
                events.append(DecodeEvent("missing", packet.seq, detail))
                self._lose_sync()
            if self._reference is None:
                events.append(DecodeEvent("waiting", packet.seq, "no reference: needs intra"))
                return Decoded((), tuple(events))
        elif self._reference is None and self.params is not None:
            events.append(DecodeEvent("resync", packet.seq))
        changes: list[np.ndarray] = []
        frames = self._frames(packet, where, changes)
        self._next_frame = (packet.first_frame + packet.count) % FRAME_MODULUS
        self.params = frames[-1][1]
        return Decoded(tuple(frames), tuple(events), tuple(changes))

    def _check_layout(self, packet, where: str) -> None:
        """A packet whose light, body motion or block map flag disagrees with the stream's
        set-up is a `PacketError` (a map stream's packet without a change goes without it)."""
        for name, present, expected in (("light", packet.light, self.units.light),
                                        ("body motion", packet.body, self.units.body),
                                        ("camera motion", packet.camera, self.units.camera),
                                        ("block map", packet.block_map, self.map_blocks > 0)):  # fmt: skip
            if present != expected and not (name == "block map" and expected):  # none: no change
                raise PacketError(
                    f"{where} (seq {packet.seq}): {name} {'present' if present else 'absent'}, "
                    f"the stream was set up {'with' if expected else 'without'} it"
                )

    def _frames(self, packet, where: str, changes: list) -> list[tuple[int, np.ndarray]]:
        """The packet's sets decoded against the reference (the new reference kept), each
        frame's block map changes into `changes`; a set no face has is a `PacketError` and
        loses sync."""
        kinds = [packet.intra] + [False] * (packet.count - 1)
        try:
            blocks = self.map_blocks if packet.block_map else 0
            indices = decode_sets(packet.words, kinds, self.models, blocks, changes)
            if self.map_blocks and not packet.block_map:  # a packet without a change
                changes += [np.zeros((0, 2), np.int64)] * packet.count
        except PacketError as err:
            self._lose_sync()
            raise PacketError(f"{where} (seq {packet.seq}): {err}") from None
        frames = []
        reference = self._reference
        code = packet.global_code
        for offset, (intra, set_indices) in enumerate(zip(kinds, indices, strict=True)):
            if intra:
                reference = self.quantiser.dequantise_intra(set_indices, code)
            else:
                reference = self.quantiser.dequantise_predictive(set_indices, reference, code)
            params = self.units.from_units(reference)
            problem = ""
            if not (np.all(np.isfinite(params)) and params[2] > 0):
                problem = "decodes to parameters no face has (scale not positive)"
            problem = problem or _light_problem(self.units.split(params)[1])
            problem = problem or _body_problem(self.units.body_of(params))
            if problem:
                self._lose_sync()
                raise PacketError(f"{where} (seq {packet.seq}): frame {offset}: {problem}")
            frames.append(((packet.first_frame + offset) % FRAME_MODULUS, params))
        self._reference = reference
        return frames


def _body_problem(body: np.ndarray | None) -> str:
    """Why a decoded body motion is absurd (on any picture up to 4096 pixels), or ""."""
    from uma.mbc.layers import body_problem

    return "" if body is None else body_problem(body, (4096, 4096))


def _light_problem(light: tuple[float, float] | None) -> str:
    """Why decoded light is absurd (outside the renderer's ranges), or ""."""
    from uma.mbc.scene_render import LIGHT_GAIN_RANGE, LIGHT_OFFSET_RANGE

    if light is None:
        return ""
    gain, offset = light
    if not LIGHT_GAIN_RANGE[0] <= gain <= LIGHT_GAIN_RANGE[1]:
        return f"light gain {gain:.3g} outside {LIGHT_GAIN_RANGE}"
    if not LIGHT_OFFSET_RANGE[0] <= offset <= LIGHT_OFFSET_RANGE[1]:
        return f"light offset {offset:.3g} levels outside {LIGHT_OFFSET_RANGE}"
    return ""


class FaceRenderer:
    """Renders the description's textured model at given parameters over a background.

    The background is the caller's picture (e.g. the last full frame received), or by default
    the description's texture pasted where it was cut from on a mid-grey picture of the
    source's size.
    """

    def __init__(
        self,
        description: ContentDescription,
        size: tuple[int, int],
        *,
        background: np.ndarray | None = None,
    ):
        width, height = size
        self.size = (int(width), int(height))
        self.description = description
        self.texture = np.ascontiguousarray(description.gray, dtype=np.uint8)
        self.texture_points = description.projected()
        self.triangles = description.model.triangles
        # What does not change between frames: each triangle's texture corners, and the pixel
        # grid (a box's grid is a view of it).
        self._texture_corners = self.texture_points[self.triangles]
        grid_y, grid_x = np.mgrid[0:height, 0:width].astype(np.float32)
        self._grid = (grid_x, grid_y)
        if background is None:
            background = np.full((height, width), 128, dtype=np.uint8)
            x0, y0 = (int(round(v)) for v in description.origin_px)
            h = min(self.texture.shape[0], height - y0)
            w = min(self.texture.shape[1], width - x0)
            if h > 0 and w > 0 and x0 >= 0 and y0 >= 0:
                background[y0 : y0 + h, x0 : x0 + w] = self.texture[:h, :w]
        self.set_background(background)

    def set_background(self, background: np.ndarray) -> None:
        background = np.asarray(background)
        if background.shape != (self.size[1], self.size[0]) or background.dtype != np.uint8:
            raise ValueError(
                f"background: expected a {self.size[0]}x{self.size[1]} uint8 gray picture, got "
                f"{background.shape} {background.dtype}"
            )
        self.background = background

    def render(self, params: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The picture (H, W) uint8 and the mask of the pixels the face covers.

        Every triangle maps picture positions to texture positions by one affine map; the
        pixels of the face's bounding box take their triangle's map (`triangle_labels`) and
        one cv2.remap reads the texture: several times cheaper than `uma.face.render.render`,
        whose per-pixel barycentric coordinates fitting needs but rendering does not.
        """
        import cv2

        from uma.face.geometry import project, visible_triangles
        from uma.face.render import barycentric_affine, triangle_labels
        from uma.mbc.layered_kernels import FAR_OUTSIDE_MAP, triangle_maps

        model = self.description.model
        width, height = self.size
        image = self.background.copy()
        mask = np.zeros((height, width), dtype=bool)
        target = project(model, params)
        x0, y0 = np.maximum(np.floor(target.min(axis=0)).astype(int), 0)
        x1 = min(int(np.ceil(target[:, 0].max())) + 1, width)
        y1 = min(int(np.ceil(target[:, 1].max())) + 1, height)
        if x1 <= x0 or y1 <= y0:
            return image, mask
        labels = triangle_labels(
            target - (x0, y0),
            self.triangles,
            (y1 - y0, x1 - x0),
            triangle_mask=visible_triangles(model, params),
        )
        # (T, 2, 3): texture (u, v) as an affine function of the box's (x, y, 1).
        affine = barycentric_affine(target - (x0, y0), self.triangles)
        maps = np.einsum("tjc,tjk->tck", self._texture_corners, affine)
        xs, ys = (g[: y1 - y0, : x1 - x0] for g in self._grid)
        # Label -1 reads far outside the texture.
        map_x, map_y = triangle_maps(labels, maps, FAR_OUTSIDE_MAP, xs, ys)
        face = labels >= 0
        patch = cv2.remap(
            self.texture, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
        )
        box = image[y0:y1, x0:x1]
        box[face] = patch[face]
        mask[y0:y1, x0:x1] = face
        return image, mask
