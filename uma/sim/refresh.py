"""The model-aided refresh's coders (docs/refresh.md): H.264 of the whole picture, one frame an
interval, beside the model codec's parameters.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in pixels; rates in
kbit/s.

The engine's `RefreshEncoder` codes the pictures the engine orders (`uma.engine.refresh`) and
decodes each again, so it holds exactly what the receiver will render from, with the pose the
model codec's stream gives that frame (its decoded parameters, which the receiver has too).
The receiver's `RefreshDecoder` decodes the refresh stream (a chain of its own: intra, then
predicted from the previous refresh).
"""

from __future__ import annotations

import numpy as np

from uma.engine.refresh import RefreshOrder

__all__ = ["RefreshEncoder", "RefreshDecoder", "refresh_size"]

# Pictures the encoder keeps for the mirror, waiting for the receiver to say it took them.
_KEPT = 8


def refresh_size(source_size: tuple[int, int], scale: float) -> tuple[int, int]:
    """The refresh's coded size: `scale` x the source's, even, at least 16 pixels."""
    return tuple(max(16, int(round(v * scale / 2.0)) * 2) for v in source_size)  # type: ignore[return-value]


class RefreshEncoder:
    """Codes refreshes (a new libx264 encoder, intra, on a change of rate) and keeps what the
    receiver will decode of each, by frame, with its pose."""

    def __init__(self, config, *, source_size: tuple[int, int]) -> None:
        self.config = config
        self.source_size = source_size
        self.size = refresh_size(source_size, config.scale)
        self.encoder = None
        self.rate_kbps = 0.0
        self.fps = 0.0
        self.decoder = None
        self.kept: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def encode(self, picture: np.ndarray, order: RefreshOrder, params: np.ndarray):
        """`picture` (source size) coded as `order` says: (bytes, intra). The receiver's
        picture of it is kept with `params` (the model's decoded pose on that frame)."""
        from uma.video import H264Decoder, H264Encoder, resize_yuv420

        width, height = self.size
        if self.encoder is None or (order.rate_kbps, order.fps) != (self.rate_kbps, self.fps):
            # A new stream (a new size, or the last refresh was not sent) starts intra.
            self.encoder = H264Encoder(
                width, height, order.fps, order.rate_kbps, preset=self.config.preset,
                keyint_frames=10_000, vbv_frames=1.0,
            )  # fmt: skip
            self.rate_kbps, self.fps = order.rate_kbps, order.fps
            intra = True
        else:
            intra = order.intra
        out = self.encoder.encode(resize_yuv420(picture, width, height), force_idr=intra)
        if out.is_keyframe or self.decoder is None:
            self.decoder = H264Decoder()
        decoded = self.decoder.decode(out.data)
        if decoded is not None:
            full = resize_yuv420(decoded, *self.source_size)
            self.kept[order.frame] = (np.ascontiguousarray(full), np.asarray(params).copy())
            for frame in sorted(self.kept)[:-_KEPT]:
                del self.kept[frame]
        return out.data, bool(out.is_keyframe)

    def discard(self, frame: int) -> None:
        """Refresh `frame` is not sent: forget it, and start the next stream intra."""
        self.kept.pop(frame, None)
        self.encoder = None

    def taken(self, frame: int) -> tuple[np.ndarray, np.ndarray] | None:
        """The picture and pose of refresh `frame` the receiver took (None: not kept)."""
        found = self.kept.get(frame)
        for older in [f for f in self.kept if f < frame]:
            del self.kept[older]
        return found


class RefreshDecoder:
    """The receiver's refresh stream: a unit's picture at the source size, or None."""

    def __init__(self, *, source_size: tuple[int, int]) -> None:
        from uma.video import H264Decoder

        self.source_size = source_size
        self.decoder = H264Decoder(conceal=False)

    def decode(self, data: bytes) -> np.ndarray | None:
        from uma.errors import VideoError
        from uma.video import resize_yuv420

        try:
            picture = self.decoder.decode(data)
        except VideoError:
            return None
        if picture is None:
            return None
        return np.ascontiguousarray(resize_yuv420(picture, *self.source_size))


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
        params = getattr(mbc_encoder, "decoded_params", lambda: None)()
        if params is None:
            return None
        data, intra = self.encoder.encode(picture, order, params)
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
            renderer = scene_renderer(mbc_encoder.description, self.source_size, mbc_encoder.mbc)
            picture = resize_yuv420(np.ascontiguousarray(receiver_picture), *self.source_size)
            renderer.set_reference(np.ascontiguousarray(picture), first)
            renderer.set_face_source(True)
            self._view = (receiver_picture, renderer)
        return self._view[1]

    def gain_db(
        self, mbc_encoder, picture: np.ndarray, frame: int, receiver_picture=None
    ) -> float | None:
        """How much better the refresh of `frame` is than what the receiver renders there, in
        luma PSNR over the face box (the model's points plus `uma.face.region`'s margin):
        against the engine's mirror once the receiver took a refresh, before that against
        `receiver_picture` at the stream's first pose; None when there is nothing to compare
        (or, with `first_always`, before the receiver took a first refresh)."""
        from uma.face.geometry import project
        from uma.face.region import points_box

        kept = self.encoder.kept.get(frame)
        mirror = getattr(mbc_encoder, "mirror", None)
        if getattr(mbc_encoder, "refresh_frame", -1) < 0:
            # Before the receiver took a refresh, the mirror is the picture the engine
            # initialised on, sharper than the receiver's last one: judge against that one.
            if self.config.first_always:
                return None
            mirror = self._receiver_view(mbc_encoder, receiver_picture)
        decoded = getattr(getattr(mbc_encoder, "stream", None), "decoded", None)
        if kept is None or mirror is None or decoded is None:
            return None
        params, light = mbc_encoder.units.split(decoded)
        width, height = self.source_size
        box = points_box(project(mbc_encoder.description.model, params), width, height)
        if box is None:
            return None
        rendered, _ = mirror.render(params, light)
        window = (slice(box.y, box.y + box.height), slice(box.x, box.x + box.width))
        truth = picture[:height][window].astype(np.float64)
        return _psnr_db(kept[0][:height][window], truth) - _psnr_db(
            rendered[:height][window], truth
        )

    def engine_adopt(self, mbc_encoder, frame: int) -> bool:
        """The receiver renders from refresh `frame`: so does the encoder's mirror."""
        taken = self.encoder.taken(frame)
        if taken is None or mbc_encoder is None or not hasattr(mbc_encoder, "set_reference"):
            return False
        picture, params = taken
        mbc_encoder.set_reference(picture, params, refresh_frame=frame)
        return True

    def receiver_decode(self, mbc_decoder, frame: int, data: bytes) -> np.ndarray | None:
        """A refresh unit of `frame` complete at the receiver: its picture (None: undecodable),
        handed to the model codec's decoder `mbc_decoder` (None: not on the model codec)."""
        picture = self.decoder.decode(data)
        if picture is not None and mbc_decoder is not None and hasattr(mbc_decoder, "refresh"):
            mbc_decoder.refresh(frame, picture)
        return picture


def _psnr_db(picture: np.ndarray, truth: np.ndarray) -> float:
    mse = float(np.mean((picture.astype(np.float64) - truth) ** 2))
    return 100.0 if mse <= 1e-10 else 10.0 * float(np.log10(255.0**2 / mse))
