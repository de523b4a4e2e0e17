"""The simulation's side of the codec registry (`uma.codecs`): each codec's coders, and the chain.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in pixels; bytes out.

Every engine-side encoder has `encode(picture, *, intra, frame) -> Coded` (bytes and what it
cost, in fitting-cost evaluations, so the engine can model compute time); every receiver-side
decoder has `decode(unit) -> {frame: picture}`. `ENCODERS` and `DECODERS` map every registered
codec name to a factory: a full-frame codec's are made from the `uma.video` classes its registry
entry names, the region and model codecs' are their own modules'. `CodecChain` holds the codecs along the path:
the sender's H.264 encoder, the engine's decoder of it, one engine encoder for the operating
point in use (a new one on a change of point), and the receiver's decoders, which dispatch on
the unit's codec and start a new reference chain (a fresh decoder) when the codec changes.
`uma bench sim` replays a run through the same chain. With `account`, wall-clock seconds spent
in codecs are summed for the benchmark; they never feed back into the simulation.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np

from uma.codecs import REGISTRY, Role, spec
from uma.config.scenario import Scenario
from uma.engine.points import OperatingPoint
from uma.sim.coded import Coded
from uma.sim.context import CodecContext
from uma.sim.face_region import FaceRegionDecoder, FaceRegionEncoder
from uma.sim.mbc_codecs import (
    MbcPointEncoder,
    MbcUnitDecoder,
    SelectedMbcEncoder,
    SenderMbc,
)
from uma.sim.packets import EncodedUnit

__all__ = [
    "CodecChain",
    "Coded",
    "FullFramePointEncoder",
    "FullFrameUnitDecoder",
    "encoder_factory",
    "decoder_factory",
    "video_class",
    "MbcPointEncoder",
    "MbcUnitDecoder",
    "SenderMbc",
    "SelectedMbcEncoder",
    "ENCODERS",
    "DECODERS",
]


class FullFramePointEncoder:
    """A full-frame codec at one operating point: its rate, size (never above the source's)
    and frame rate, coded by the `uma.video` class its registry entry names."""

    def __init__(self, point: OperatingPoint, *, source_size, source_fps, settings, context=None):
        self.width = min(point.width, source_size[0])
        self.height = min(point.height, source_size[1])
        self.encoder = video_class(point.codec, "video_encoder")(
            self.width,
            self.height,
            min(point.fps, source_fps),
            point.rate_kbps,
            **settings.kwargs(),
        )

    def encode(self, picture: np.ndarray, *, intra: bool, frame: int = -1) -> Coded:
        from uma.video import resize_yuv420

        if (picture.shape[1], picture.shape[0] * 2 // 3) != (self.width, self.height):
            picture = resize_yuv420(picture, self.width, self.height)
        out = self.encoder.encode(picture, force_idr=intra)
        return Coded(out.data, bool(out.is_keyframe), self.width, self.height)


class FullFrameUnitDecoder:
    """A full-frame codec's decoder: {frame: picture}, or {} for a unit it cannot decode."""

    def __init__(self, *, context=None, codec: str = "h264") -> None:
        self.decoder = video_class(codec, "video_decoder")()

    def decode(self, unit: EncodedUnit) -> dict[int, np.ndarray]:
        from uma.errors import VideoError

        try:
            picture = self.decoder.decode(unit.data)
        except VideoError:
            return {}
        return {} if picture is None else {unit.frame: picture}


def video_class(codec: str, role: str):
    """The `uma.video` class that `codec`'s registry entry names as its `role`
    (`video_encoder` or `video_decoder`)."""
    import uma.video

    name = getattr(spec(codec), role)
    found = getattr(uma.video, name, None) if name else None
    if found is None:
        raise LookupError(f"codec {codec!r}: uma.video has no {role} {name!r}")
    return found


# The coders of the roles that are not full-frame ladders (one codec each); a full-frame codec
# needs none here: its registry entry names its `uma.video` classes.
_OWN_CODERS: dict[Role, tuple[Callable[..., Any], Callable[..., Any]]] = {
    Role.REGION: (FaceRegionEncoder, FaceRegionDecoder),
    Role.MODEL: (MbcPointEncoder, MbcUnitDecoder),
}


def encoder_factory(codec: str, *, selection: bool = False) -> Callable[..., Any]:
    """What makes `codec`'s engine-side encoder (the selection scheme's for a model codec)."""
    if spec(codec).role is Role.FULL_FRAME:
        return FullFramePointEncoder
    if selection and spec(codec).role is Role.MODEL:
        return SelectedMbcEncoder
    return _OWN_CODERS[spec(codec).role][0]


def decoder_factory(codec: str) -> Callable[..., Any]:
    """What makes `codec`'s receiver-side decoder (called with `context=`)."""
    if spec(codec).role is Role.FULL_FRAME:
        return partial(FullFrameUnitDecoder, codec=codec)
    return _OWN_CODERS[spec(codec).role][1]


ENCODERS: dict[str, Callable[..., Any]] = {name: encoder_factory(name) for name in REGISTRY}
DECODERS: dict[str, Callable[..., Any]] = {name: decoder_factory(name) for name in REGISTRY}


class CodecChain:
    """The codecs along the path; one engine encoder per operating point, made on a change."""

    def __init__(
        self,
        scenario: Scenario,
        ladder,
        points: tuple[OperatingPoint, ...],
        *,
        width: int,
        height: int,
        fps: float,
        account: bool = False,
        description=None,
    ) -> None:
        from uma.video import H264Decoder, H264Encoder

        self.scenario = scenario
        self.ladder = ladder
        self.points = points
        self.fps = fps
        self.width, self.height = width, height
        self.sender_encoder = H264Encoder(
            width,
            height,
            fps,
            scenario.sender.rate_kbps,
            preset=scenario.sender.preset,
            keyint_frames=scenario.sender.keyint_frames,
        )
        self.engine_decoder = H264Decoder()
        self.context = CodecContext(
            description=description,
            seed=scenario.seed,
            source_size=(width, height),
            face_region=scenario.engine.face_region,
            mbc=scenario.engine.mbc,
            fps=fps,
        )
        self.refresh = None  # the model-aided refresh's coders (`uma.sim.refresh`)
        if description is not None and scenario.engine.mbc.refresh.enabled:
            from uma.sim.refresh import RefreshChain

            self.refresh = RefreshChain(scenario.engine.mbc.refresh, source_size=(width, height))
        if description is not None:
            from uma.mbc import StreamConfig

            self.context.stream = StreamConfig(
                frames_per_packet=scenario.engine.mbc.frames_per_packet
            )
        # The customisation scheme: `adaptation` (the engine tracks the face in the H.264 it
        # receives) or `selection` (the sender tracks and sends the parameters up too).
        self.sender_mbc: SenderMbc | None = None
        self.uplink_mbc = None
        if description is not None and scenario.engine.mbc.scheme == "selection":
            from dataclasses import replace

            from uma.mbc import FaceUnits, ParameterDecoder

            mbc = scenario.engine.mbc
            self.sender_mbc = SenderMbc(
                self.context,
                init_us_per_evaluation=mbc.init_us_per_evaluation,
                track_us_per_evaluation=mbc.track_us_per_evaluation,
            )
            units = FaceUnits.of(description.model, description.params)
            stream = replace(self.context.stream, frames_per_packet=1)
            self.uplink_mbc = ParameterDecoder(units, stream)
            self.context.selected = {}
        self._settings: dict[str, Any] = {}  # encoder settings of other codecs' ladders
        self.engine_encoder = None
        self.engine_point = -1
        self.pending_mbc = None  # the MBC encoder an initialisation is preparing
        self.receiver_decoder = None
        self.receiver_codec = ""
        self.receiver_last: np.ndarray | None = None
        self.account = account
        self.seconds = 0.0
        self.codec_seconds: dict[str, float] = {}

    def _timed(self, codec: str, fn, *args, **kwargs):
        if not self.account:
            return fn(*args, **kwargs)
        start = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            spent = time.perf_counter() - start
            self.seconds += spent
            self.codec_seconds[codec] = self.codec_seconds.get(codec, 0.0) + spent

    def sender_encode(self, frame: np.ndarray):
        return self._timed("h264", self.sender_encoder.encode, frame)

    def sender_side_data(self, frame: np.ndarray, index: int) -> bytes | None:
        """Selection: the sender's parameter packet for source frame `index` (None otherwise)."""
        if self.sender_mbc is None:
            return None
        return self._timed("mbc", self.sender_mbc.encode, frame, frame=index)

    def engine_receive_side(self, data: bytes | None, index: int) -> None:
        """Selection: decode the parameters the sender sent up with frame `index`."""
        if self.uplink_mbc is None:
            return
        from uma.mbc import PacketError

        selected = self.context.selected
        selected.pop(index - 2 * int(self.fps), None)  # frames never selected need not stay
        if not data:
            return
        try:
            out = self.uplink_mbc.decode(data)
        except PacketError:
            return
        if out.frames:
            selected[index] = out.frames[-1][1]

    def engine_decode(self, encoded) -> np.ndarray | None:
        return self._timed("h264", self.engine_decoder.decode, encoded.data)

    def rung_size(self, index: int) -> tuple[int, int]:
        """The point's picture size, never larger than the source's (upscaling adds only bits)."""
        point = self.points[index]
        return min(point.width, self.width), min(point.height, self.height)

    def _make_encoder(self, index: int):
        point = self.points[index]
        factory = encoder_factory(point.codec, selection=self.sender_mbc is not None)
        return factory(
            point,
            source_size=(self.width, self.height),
            source_fps=self.fps,
            settings=self.settings(point.codec),
            context=self.context,
        )

    def settings(self, codec: str):
        """The encoder settings `codec` is coded with: the run's ladder's for the run's
        full-frame codec, for a codec coded with it (`CodecSpec.codes_with`) and for a codec
        with no ladder (the model codec, which takes none); else the settings of the ladder
        file of the codec it is coded with."""
        with_codec = spec(codec).codes_with or codec
        if with_codec == self.scenario.engine.codec or spec(with_codec).ladder is None:
            return self.ladder.encoder
        if with_codec not in self._settings:
            from uma.paths import codecs_dir
            from uma.video import load_ladder

            ladder = load_ladder(codecs_dir() / spec(with_codec).ladder)
            self._settings[with_codec] = ladder.encoder
        return self._settings[with_codec]

    def initialise_model(self, picture: np.ndarray, index: int, *, frame: int):
        """Initialise a new MBC encoder for point `index` on `picture`; it is used from the
        first frame coded at that point."""
        encoder = self._make_encoder(index)
        result = self._timed(self.points[index].codec, encoder.initialise, picture, frame=frame)
        self.pending_mbc = encoder if result else None
        return result

    def engine_encode(
        self, picture: np.ndarray, index: int, *, force_idr: bool, frame: int = -1
    ) -> Coded:
        """Code `picture` at point `index`, intra when `force_idr` (the engine's decision: it
        asks for intra on a change of point, which starts a new encoder here)."""
        point = self.points[index]
        if index != self.engine_point:
            # A new point is a new stream: new codec, size or rate.
            if self.pending_mbc is not None and spec(point.codec).role is Role.MODEL:
                self.engine_encoder, self.pending_mbc = self.pending_mbc, None
            else:
                self.engine_encoder = self._timed(point.codec, self._make_encoder, index)
            self.engine_point = index
        return self._timed(
            point.codec, self.engine_encoder.encode, picture, intra=force_idr, frame=frame
        )

    def receiver_decode(self, unit: EncodedUnit) -> dict[int, np.ndarray]:
        if unit.codec != self.receiver_codec:
            # A new codec is a new reference chain, rendered over the last picture shown.
            self.context.background = self.receiver_last
            self.receiver_decoder = DECODERS[unit.codec](context=self.context)
            self.receiver_codec = unit.codec
        pictures = self._timed(unit.codec, self.receiver_decoder.decode, unit)
        if pictures:
            self.receiver_last = pictures[max(pictures)]
        return pictures

    def engine_refresh(self, picture: np.ndarray, order):
        """Code the refresh `order` (`uma.engine.refresh.RefreshOrder`) of `picture`, the
        frame the model codec just coded: (bytes, intra, gain_db), or None."""
        if self.refresh is None:
            return None
        # The engine knows the last picture the receiver decoded before this stretch on the
        # model codec (its reports say which), once the receiver is on it.
        on_model = self.receiver_codec and spec(self.receiver_codec).role is Role.MODEL
        receiver_picture = self.context.background if on_model else None
        return self._timed(
            "refresh", self.refresh.engine_code, self.engine_encoder, picture, order,
            receiver_picture=receiver_picture,
        )  # fmt: skip

    def engine_discard_refresh(self, frame: int) -> None:
        """The engine does not send the refresh of `frame` just coded."""
        if self.refresh is not None:
            self.refresh.discard(frame)

    def engine_adopt_refresh(self, frame: int) -> None:
        """The receiver renders from refresh `frame` now: the engine's mirror follows."""
        if self.refresh is not None:
            self.refresh.engine_adopt(self.engine_encoder, frame)

    def receiver_refresh(self, unit: EncodedUnit) -> np.ndarray | None:
        """A refresh unit complete at the receiver: its picture, or None (undecodable)."""
        if self.refresh is None:
            return None
        on_model = self.receiver_codec and spec(self.receiver_codec).role is Role.MODEL
        mbc = self.receiver_decoder if on_model else None
        return self._timed("refresh", self.refresh.receiver_decode, mbc, unit.frame, unit.data)

    def receiver_refresh_frame(self) -> int:
        """The refresh the receiver's model codec renders from (-1: none)."""
        return getattr(self.receiver_decoder, "refresh_frame", -1)

    def engine_flush(self) -> Coded | None:
        """What the engine's encoder still holds (MBC's open packet) when it leaves its point."""
        flush = getattr(self.engine_encoder, "flush", None)
        if flush is None:
            return None
        return self._timed(self.points[self.engine_point].codec, flush)
