"""The model-aided refresh's coders in a run (docs/refresh.md): `uma.mbc.RefreshCoder`, the
one refresh coder `uma bench mbc` uses too, beside the model codec's parameters.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in pixels; rates in
kbit/s.

A refresh codes a box around the face (`FACE_MARGIN` x the model's extent at the decoded pose
when its stream starts, a multiple of 16 pixels) at `FACE_SCALE` of its size, one frame an
interval, by libx264; the box's corner on that frame travels in the unit's first 4 bytes (two
16-bit numbers: `uma.mbc.POSITION_BITS`), the H.264 unit after it. The engine's
`RefreshEncoder` codes the pictures the engine orders (`uma.engine.refresh`) and keeps what the
receiver will decode of each, by frame, with the model stream's decoded set of that frame (the
receiver has it too); the receiver's `RefreshDecoder` decodes the refresh stream (intra, then
predicted from the previous refresh). Both ends take a refresh by `uma.mbc.take_refresh`.
"""

from __future__ import annotations

import struct

import numpy as np

from uma.engine.refresh import RefreshOrder

__all__ = ["RefreshEncoder", "RefreshDecoder", "RefreshChain", "FACE_MARGIN", "FACE_SCALE"]

# Pictures the encoder keeps for the mirror, waiting for the receiver to say it took them.
_KEPT = 8
FACE_MARGIN = 1.6  # the box: this many times the model's extent (as `uma bench mbc`)
# The box coded at this fraction of its size. `uma bench mbc` codes 0.625 at its own cadence of
# small units (docs/refresh.md, session refresh2); at the engine's cadence 0.625 moved the
# default commute within noise, so this stayed.
FACE_SCALE = 0.5
_CORNER = struct.Struct(">HH")


class RefreshEncoder:
    """Codes refreshes (a new `uma.mbc.RefreshCoder`, so a new intra stream, on a change of
    rate or frame rate and on an intra order) and keeps what the receiver will decode of each,
    by frame, with its decoded set."""

    def __init__(self, config, *, source_size: tuple[int, int]) -> None:
        self.config = config
        self.source_size = tuple(source_size)
        self.coder = None
        self.box: tuple[int, int] | None = None
        self.rate_kbps = 0.0
        self.fps = 0.0
        self.kept: dict[int, tuple[object, np.ndarray]] = {}

    def _settings(self) -> dict:
        return {"preset": self.config.preset, "keyint_frames": 10_000, "vbv_frames": 1.0}

    def encode(self, picture: np.ndarray, order: RefreshOrder, model, values: np.ndarray, units):
        """`picture` (source size) coded as `order` says around the face of `model` at the
        decoded set `values` (`units` split it): (bytes, intra). The receiver's picture of it
        (corner, box picture) is kept with `values`."""
        from uma.mbc import RefreshCoder
        from uma.mbc.refresh_coder import box_corner, even_px, face_box_size

        params = units.split(values)[0]
        fresh = (order.rate_kbps, order.fps) != (self.rate_kbps, self.fps)
        if self.coder is None or fresh or order.intra:
            # A new stream (a new rate, or the last refresh was not sent) starts intra.
            self.box = face_box_size(model, params, FACE_MARGIN, self.source_size)
            coded = tuple(even_px(v * FACE_SCALE) for v in self.box)
            self.coder = RefreshCoder(
                self.source_size, coded, order.fps, order.rate_kbps, self._settings(), self.box
            )
            self.rate_kbps, self.fps = order.rate_kbps, order.fps
        corner = box_corner(model, params, self.box, self.source_size)
        _, intra, decoded = self.coder.code(picture, corner)
        if decoded is not None:
            self.kept[order.frame] = (decoded, np.asarray(values).copy())
            for frame in sorted(self.kept)[:-_KEPT]:
                del self.kept[frame]
        return _CORNER.pack(*corner) + self.coder.data, intra

    def discard(self, frame: int) -> None:
        """Refresh `frame` is not sent: forget it, and start the next stream intra."""
        self.kept.pop(frame, None)
        self.coder = None

    def taken(self, frame: int) -> tuple[object, np.ndarray] | None:
        """The decoded picture and set of refresh `frame` the receiver took (None: not kept)."""
        found = self.kept.get(frame)
        for older in [f for f in self.kept if f < frame]:
            del self.kept[older]
        return found


class RefreshDecoder:
    """The receiver's refresh stream: a unit's ((x0, y0), box picture), or None. The box is
    the decoded picture's size over `FACE_SCALE`."""

    def __init__(self, *, source_size: tuple[int, int]) -> None:
        from uma.video import H264Decoder

        self.source_size = tuple(source_size)
        self.decoder = H264Decoder(conceal=False)

    def decode(self, data: bytes):
        from uma.errors import VideoError
        from uma.mbc.refresh_coder import even_px
        from uma.video import resize_yuv420

        if len(data) <= _CORNER.size:
            return None
        corner = _CORNER.unpack_from(data)
        try:
            picture = self.decoder.decode(data[_CORNER.size :])
        except VideoError:
            return None
        if picture is None:
            return None
        coded_w, coded_h = picture.shape[1], picture.shape[0] * 2 // 3
        box = (even_px(coded_w / FACE_SCALE), even_px(coded_h / FACE_SCALE))
        if corner[0] + box[0] > self.source_size[0] or corner[1] + box[1] > self.source_size[1]:
            return None  # not a box of this picture
        return corner, np.ascontiguousarray(resize_yuv420(picture, *box))


class RefreshChain:
    """The refresh's two ends in a run's `CodecChain`: the engine's encoder (and its mirror
    of what the receiver renders from) and the receiver's decoder, talking to the model
    codec's coders the chain holds."""

    def __init__(self, config, *, source_size: tuple[int, int]) -> None:
        self.config = config
        self.encoder = RefreshEncoder(config, source_size=source_size)
        self.decoder = RefreshDecoder(source_size=source_size)
        self.source_size = source_size
        self._view = None  # (the receiver's picture, its renderer) before the first refresh

    def engine_code(
        self, mbc_encoder, picture: np.ndarray, order: RefreshOrder, *, receiver_picture=None
    ):
        """Code the refresh `order` names of `picture`, which `mbc_encoder` (the engine's
        model codec) has just coded: (bytes, intra, gain_db), or None when it has no pose for
        it. `gain_db` is how much it beats what the receiver renders now (`gain_db`; None:
        nothing to compare): whether that is worth sending is the engine's decision
        (`uma.engine.refresh`), and `discard` forgets one that is not.
        `receiver_picture`: the picture the receiver's model codec started its stretch from
        (the last it decoded before; None: not known yet)."""
        values = getattr(getattr(mbc_encoder, "stream", None), "decoded", None)
        if values is None:
            return None
        model, units = mbc_encoder.description.model, mbc_encoder.units
        data, intra = self.encoder.encode(picture, order, model, values, units)
        return data, intra, self.gain_db(mbc_encoder, picture, order.frame, receiver_picture)

    def discard(self, frame: int) -> None:
        """The refresh of `frame` just coded is not sent: the next one starts intra."""
        self.encoder.discard(frame)

    def _receiver_view(self, mbc_encoder, receiver_picture):
        """What the receiver renders from before its first refresh: `receiver_picture` at
        the stream's first decoded pose, the face from the description (as
        `MbcUnitDecoder` does); None when that is not known."""
        from uma.sim.mbc_codecs import scene_renderer
        from uma.video import resize_yuv420

        first = getattr(mbc_encoder, "first_params", None)
        if receiver_picture is None or first is None:
            return None
        if self._view is None or self._view[0] is not receiver_picture:
            renderer = scene_renderer(
                mbc_encoder.description, self.source_size, mbc_encoder.mbc,
                layered=getattr(mbc_encoder, "layered", True),
            )  # fmt: skip
            picture = resize_yuv420(np.ascontiguousarray(receiver_picture), *self.source_size)
            renderer.set_reference(np.ascontiguousarray(picture), first)
            renderer.set_face_source(True)
            self._view = (receiver_picture, renderer)
        return self._view[1]

    def gain_db(
        self, mbc_encoder, picture: np.ndarray, frame: int, receiver_picture=None
    ) -> float | None:
        """How much better the refresh of `frame` is than what the receiver renders there
        (`uma.mbc.refresh_gain_db`): against the engine's mirror once the receiver took a
        refresh, before that against `receiver_picture` at the stream's first pose; None when
        there is nothing to compare or the engine's decision cannot depend on it
        (`uma.mbc.needs_judging`), so the mirror draws nothing."""
        from uma.mbc import needs_judging, refresh_gain_db

        taken = getattr(mbc_encoder, "refresh_frame", -1) >= 0
        config = self.config
        if not needs_judging(config.min_gain_db, first_always=config.first_always,
                             refresh_taken=taken):  # fmt: skip
            return None
        kept = self.encoder.kept.get(frame)
        # Before the receiver took a refresh, the mirror is the picture the engine initialised
        # on, sharper than the receiver's last one: judge against what the receiver shows.
        mirror = (
            getattr(mbc_encoder, "mirror", None)
            if taken
            else self._receiver_view(mbc_encoder, receiver_picture)
        )
        if kept is None or mirror is None:
            return None
        (corner, patch), values = kept[0], kept[1]
        return refresh_gain_db(mirror, mbc_encoder.units, values, corner, patch, picture)

    def engine_adopt(self, mbc_encoder, frame: int) -> bool:
        """The receiver renders from refresh `frame`: so does the encoder's mirror."""
        from uma.mbc import SceneError

        taken = self.encoder.taken(frame)
        if taken is None or mbc_encoder is None or not hasattr(mbc_encoder, "take_refresh"):
            return False
        picture, values = taken
        try:
            mbc_encoder.take_refresh(values, picture, refresh_frame=frame)
        except SceneError:
            return False  # as the receiver: the old reference stays
        return True

    def receiver_decode(self, mbc_decoder, frame: int, data: bytes) -> np.ndarray | None:
        """A refresh unit of `frame` complete at the receiver, handed to the model codec's
        decoder `mbc_decoder` (None: not on the model codec): the whole picture of `frame` when
        that decoder took it now, else the decoded ((x0, y0), box picture) (nothing to show by
        itself), None when undecodable."""
        picture = self.decoder.decode(data)
        takes = mbc_decoder is not None and hasattr(mbc_decoder, "refresh")
        if picture is not None and takes and mbc_decoder.refresh(frame, picture):
            # Taken now: the frame's best picture is the new reference (box pasted in).
            return mbc_decoder.renderer.reference.copy()
        return picture
