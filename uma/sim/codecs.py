"""The codec registry: one encoder and one decoder per codec name, and the codec work of a run.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in pixels; bytes out.

Every engine-side encoder has `encode(picture, *, intra, frame) -> Coded` (bytes and what it
cost, in fitting-cost evaluations, so the engine can model compute time); every receiver-side
decoder has `decode(unit) -> picture | None`. `ENCODERS` and `DECODERS` map a codec name
(`uma.engine.points.CODECS`) to a factory. `CodecChain` holds the codecs along the path:
the sender's H.264 encoder, the engine's decoder of it, one engine encoder for the operating
point in use (a new one on a change of point), and the receiver's decoders, which dispatch on
the unit's codec and start a new reference chain (a fresh decoder) when the codec changes.
`uma bench sim` replays a run through the same chain. With `account`, wall-clock seconds spent
in codecs are summed for the benchmark; they never feed back into the simulation.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from uma.config.scenario import Scenario
from uma.engine.points import OperatingPoint
from uma.sim.coded import Coded
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
    "H264PointEncoder",
    "H264UnitDecoder",
    "MbcPointEncoder",
    "MbcUnitDecoder",
    "SenderMbc",
    "SelectedMbcEncoder",
    "ENCODERS",
    "DECODERS",
]


class H264PointEncoder:
    """libx264 at one operating point: its rate, size (never above the source's) and rate."""

    def __init__(self, point: OperatingPoint, *, source_size, source_fps, settings, context=None):
        from uma.video import H264Encoder

        self.width = min(point.width, source_size[0])
        self.height = min(point.height, source_size[1])
        self.encoder = H264Encoder(
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


class H264UnitDecoder:
    """FFmpeg's H.264 decoder: {frame: picture}, or {} for a unit it cannot decode."""

    def __init__(self, *, context=None) -> None:
        from uma.video import H264Decoder

        self.decoder = H264Decoder()

    def decode(self, unit: EncodedUnit) -> dict[int, np.ndarray]:
        from uma.errors import VideoError

        try:
            picture = self.decoder.decode(unit.data)
        except VideoError:
            return {}
        return {} if picture is None else {unit.frame: picture}


ENCODERS: dict[str, Callable[..., Any]] = {
    "h264": H264PointEncoder,
    "h264-face": FaceRegionEncoder,
    "mbc": MbcPointEncoder,
}
DECODERS: dict[str, Callable[..., Any]] = {
    "h264": H264UnitDecoder,
    "h264-face": FaceRegionDecoder,
    "mbc": MbcUnitDecoder,
}


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
        self.context: dict[str, Any] = {
            "description": description,
            "seed": scenario.seed,
            "source_size": (width, height),
            "stream": None,
            "face_region": scenario.engine.face_region,
        }
        if description is not None:
            from uma.mbc import StreamConfig

            self.context["stream"] = StreamConfig(
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
            stream = replace(self.context["stream"], frames_per_packet=1)
            self.uplink_mbc = ParameterDecoder(units, stream)
            self.context["selected"] = {}
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

    def sender_encode_mbc(self, frame: np.ndarray, index: int) -> bytes | None:
        """Selection: the sender's parameter packet for source frame `index` (None otherwise)."""
        if self.sender_mbc is None:
            return None
        return self._timed("mbc", self.sender_mbc.encode, frame, frame=index)

    def engine_receive_mbc(self, data: bytes | None, index: int) -> None:
        """Selection: decode the parameters the sender sent up with frame `index`."""
        if self.uplink_mbc is None:
            return
        from uma.mbc import PacketError

        selected = self.context["selected"]
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
        factory = ENCODERS[point.codec]
        if point.codec == "mbc" and self.sender_mbc is not None:
            factory = SelectedMbcEncoder
        return factory(
            point,
            source_size=(self.width, self.height),
            source_fps=self.fps,
            settings=self.ladder.encoder,
            context=self.context,
        )

    def mbc_initialise(self, picture: np.ndarray, index: int, *, frame: int):
        """Initialise a new MBC encoder for point `index` on `picture`; it is used from the
        first frame coded at that point."""
        encoder = self._make_encoder(index)
        result = self._timed("mbc", encoder.initialise, picture, frame=frame)
        self.pending_mbc = encoder if result else None
        return result

    def engine_encode(
        self, picture: np.ndarray, index: int, *, force_idr: bool, frame: int = -1
    ) -> Coded:
        point = self.points[index]
        if index != self.engine_point:
            # A new point is a new stream: new codec, size or rate, starting intra.
            if point.codec == "mbc" and self.pending_mbc is not None:
                self.engine_encoder, self.pending_mbc = self.pending_mbc, None
            else:
                self.engine_encoder = self._timed(point.codec, self._make_encoder, index)
            self.engine_point = index
            force_idr = True
        return self._timed(
            point.codec, self.engine_encoder.encode, picture, intra=force_idr, frame=frame
        )

    def receiver_decode(self, unit: EncodedUnit) -> dict[int, np.ndarray]:
        if unit.codec != self.receiver_codec:
            # A new codec is a new reference chain, rendered over the last picture shown.
            self.context["background"] = self.receiver_last
            self.receiver_decoder = DECODERS[unit.codec](context=self.context)
            self.receiver_codec = unit.codec
        pictures = self._timed(unit.codec, self.receiver_decoder.decode, unit)
        if pictures:
            self.receiver_last = pictures[max(pictures)]
        return pictures

    def engine_flush(self) -> Coded | None:
        """What the engine's encoder still holds (MBC's open packet) when it leaves its point."""
        flush = getattr(self.engine_encoder, "flush", None)
        if flush is None:
            return None
        return self._timed(self.points[self.engine_point].codec, flush)
