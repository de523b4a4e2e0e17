"""The codecs along the path in their three roles: the sender's, the engine's, the receiver's.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in pixels; bytes out.

Each role looks its classes up in the registry (`uma.codecs`, through
`uma.sim.coder_factories`) and names no codec: the sender codes the camera with the uplink
codec (`uplink_name()`) at its own rate and, with the selection scheme, tracks the face and
sends the parameters up; the engine decodes that, codes each picture at the operating point
the engine chose (a new encoder on a change of point; a model codec's is the one its
initialisation prepared) and, with the refresh, the refresh's engine end; the receiver decodes
each unit with its codec's decoder (a fresh one, drawn over the last picture shown, when the
codec changes) and the refresh's receiver end. With `account`, the wall-clock seconds each
spends in codecs are summed (`CodecClock`) for `uma bench sim`; they never feed back.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np

from uma.codecs import Role, model_names, spec, uplink_name
from uma.engine.points import OperatingPoint, same_stream
from uma.sim.coded import Coded
from uma.sim.coder_factories import DECODERS, encoder_factory, video_class
from uma.sim.context import CodecContext
from uma.sim.mbc_codecs import SenderMbc
from uma.sim.packets import EncodedUnit
from uma.sim.uplink import UplinkMemo, UplinkReceiver, UplinkSender, settings_key

__all__ = ["CodecClock", "SenderCoder", "EngineCoder", "ReceiverCoder", "compute_uplink"]


class CodecClock:
    """Wall-clock seconds spent in codecs, in all and per codec (only with `account`)."""

    def __init__(self, account: bool) -> None:
        self.account = account
        self.seconds = 0.0
        self.codec_seconds: dict[str, float] = {}

    def timed(self, codec: str, fn, *args, **kwargs):
        if not self.account:
            return fn(*args, **kwargs)
        start = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            spent = time.perf_counter() - start
            self.seconds += spent
            self.codec_seconds[codec] = self.codec_seconds.get(codec, 0.0) + spent


class SenderCoder:
    """The sender: the camera in the uplink codec at `sender.rate_kbps`; with the selection
    scheme (`tracker` a `SenderMbc`), the parameters of its own tracker ride along."""

    def __init__(self, scenario, *, width: int, height: int, fps: float, clock: CodecClock,
                 tracker: SenderMbc | None = None, memo: UplinkMemo | None = None) -> None:  # fmt: skip
        sender = scenario.sender
        self.codec = uplink_name()
        self.encoder = video_class(self.codec, "video_encoder")(
            width, height, fps, sender.rate_kbps, preset=sender.preset,
            keyint_frames=sender.keyint_frames,
        )  # fmt: skip
        if memo is not None:  # the stream computed once (`uma.sim.uplink`)
            start = settings_key(self.codec, sender, width=width, height=height, fps=fps)
            self.encoder = UplinkSender(self.encoder, memo, start)
        self.clock, self.tracker = clock, tracker

    def encode(self, frame: np.ndarray):
        return self.clock.timed(self.codec, self.encoder.encode, frame)

    def side_data(self, frame: np.ndarray, index: int) -> bytes | None:
        """Selection: the sender's parameter packet for source frame `index` (None otherwise)."""
        if self.tracker is None:
            return None
        return self.clock.timed(model_names()[0], self.tracker.encode, frame, frame=index)


class EngineCoder:
    """The engine's codecs: the uplink's decoder, and one encoder for the point in use."""

    def __init__(
        self, scenario, ladder, points: tuple[OperatingPoint, ...], context: CodecContext, *,
        width: int, height: int, fps: float, clock: CodecClock, uplink_params=None, refresh=None,
        memo: UplinkMemo | None = None,
    ) -> None:  # fmt: skip
        self.scenario, self.ladder, self.points, self.context = scenario, ladder, points, context
        self.width, self.height, self.fps, self.clock = width, height, fps, clock
        self.decoder = video_class(uplink_name(), "video_decoder")()
        self.uplink = None if memo is None else UplinkReceiver(self.decoder, memo)
        self.uplink_params = uplink_params  # selection: the decoder of the sender's parameters
        self.refresh = refresh  # the refresh's two ends (`uma.sim.refresh.RefreshChain`)
        self._settings: dict[str, Any] = {}  # encoder settings of other codecs' ladders
        self.encoder = None
        self.point = -1
        self.pending_model = None  # the model codec's encoder an initialisation prepares

    def decode(self, encoded) -> np.ndarray | None:
        if self.uplink is not None:  # the picture from the memo, or decoded and kept there
            return self.clock.timed(uplink_name(), self.uplink.decode, encoded)
        return self.clock.timed(uplink_name(), self.decoder.decode, encoded.data)

    def receive_side(self, data: bytes | None, index: int) -> None:
        """Selection: decode the parameters the sender sent up with frame `index`."""
        if self.uplink_params is None:
            return
        from uma.mbc import PacketError

        selected = self.context.selected
        selected.pop(index - 2 * int(self.fps), None)  # frames never selected need not stay
        if not data:
            return
        try:
            out = self.uplink_params.decode(data)
        except PacketError:
            return
        if out.frames:
            selected[index] = out.frames[-1][1]

    def make_encoder(self, index: int):
        point = self.points[index]
        factory = encoder_factory(point.codec, selection=self.uplink_params is not None)
        span = {"span": self.span(index)} if spec(point.codec).role is Role.FULL_FRAME else {}
        return factory(
            point, source_size=(self.width, self.height), source_fps=self.fps,
            settings=self.settings(point.codec), context=self.context, **span,
        )  # fmt: skip

    def span(self, index: int) -> tuple[float, float]:
        """(fps, max_rate_kbps) to open point `index`'s encoder with so that it reaches every
        point of its codec and size (as `uma.video.Ladder.open_span`)."""
        from uma.video import open_span

        point = self.points[index]
        return open_span([p for p in self.points if same_stream(p, point)])

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
        """Initialise a new model-codec encoder for point `index` on `picture`; it is used
        from the first frame coded at that point."""
        encoder = self.make_encoder(index)
        result = self.clock.timed(self.points[index].codec, encoder.initialise, picture,
                                  frame=frame)  # fmt: skip
        self.pending_model = encoder if result else None
        return result

    def encode(self, picture: np.ndarray, index: int, *, force_idr: bool, frame: int = -1) -> Coded:
        """Code `picture` at point `index`, intra when `force_idr` (the engine's decision: it
        asks for intra on a change of point, which starts a new encoder here)."""
        point = self.points[index]
        if index != self.point and self._retarget(index):
            self.point = index  # the same stream at a new rate (a keyframe only if asked)
        elif index != self.point:
            # A new point is a new stream: new codec or size (or an encoder deaf to its rate).
            if self.pending_model is not None and spec(point.codec).role is Role.MODEL:
                self.encoder, self.pending_model = self.pending_model, None
            else:
                self.encoder = self.clock.timed(point.codec, self.make_encoder, index)
            self.point = index
        return self.clock.timed(point.codec, self.encoder.encode, picture, intra=force_idr,
                                frame=frame)  # fmt: skip

    def _retarget(self, index: int) -> bool:
        """Point `index` continues the open encoder's stream and the encoder took its rate."""
        if self.encoder is None or self.point < 0:
            return False
        if not same_stream(self.points[index], self.points[self.point]):
            return False
        retarget = getattr(self.encoder, "retarget", None)
        return retarget is not None and retarget(self.points[index])

    def flush(self) -> Coded | None:
        """What the encoder still holds (a model codec's open packet) when it leaves its point."""
        flush = getattr(self.encoder, "flush", None)
        if flush is None:
            return None
        return self.clock.timed(self.points[self.point].codec, flush)

    def code_refresh(self, picture: np.ndarray, order, receiver_picture):
        """Code the refresh `order` of `picture`, the frame the model codec just coded:
        (bytes, intra, gain_db), or None."""
        if self.refresh is None:
            return None
        return self.clock.timed(
            "refresh", self.refresh.engine_code, self.encoder, picture, order,
            receiver_picture=receiver_picture,
        )  # fmt: skip

    def discard_refresh(self, frame: int) -> None:
        if self.refresh is not None:
            self.refresh.discard(frame)

    def adopt_refresh(self, frame: int) -> None:
        """The receiver renders from refresh `frame` now: the encoder's mirror follows."""
        if self.refresh is not None:
            self.refresh.engine_adopt(self.encoder, frame)


class ReceiverCoder:
    """The receiver's decoders: one reference chain per run of units of one codec."""

    def __init__(self, context: CodecContext, *, clock: CodecClock, refresh=None) -> None:
        self.context, self.clock, self.refresh = context, clock, refresh
        self.decoder = None
        self.codec = ""
        self.last: np.ndarray | None = None

    def decode(self, unit: EncodedUnit) -> dict[int, np.ndarray]:
        if unit.codec != self.codec:
            # A new codec is a new reference chain, rendered over the last picture shown.
            self.context.background = self.last
            self.decoder = DECODERS[unit.codec](context=self.context)
            self.codec = unit.codec
        pictures = self.clock.timed(unit.codec, self.decoder.decode, unit)
        if pictures:
            self.last = pictures[max(pictures)]
        return pictures

    @property
    def on_model(self) -> bool:
        return bool(self.codec) and spec(self.codec).role is Role.MODEL

    def decode_refresh(self, unit: EncodedUnit) -> np.ndarray | None:
        """A refresh unit complete: its picture, or None (undecodable)."""
        if self.refresh is None:
            return None
        model = self.decoder if self.on_model else None
        return self.clock.timed("refresh", self.refresh.receiver_decode, model, unit.frame,
                                unit.data)  # fmt: skip

    def refresh_frame(self) -> int:
        """The refresh the receiver's model codec renders from (-1: none)."""
        return getattr(self.decoder, "refresh_frame", -1)


def selection_coders(context: CodecContext, description, section):
    """The selection scheme's two ends: the sender's tracker and the engine's decoder of its
    parameters (it sets `context.selected`); `section` is the model codec's configuration."""
    from uma.mbc import FaceUnits, ParameterDecoder

    sender = SenderMbc(
        context, init_us_per_evaluation=section.init_us_per_evaluation,
        track_us_per_evaluation=section.track_us_per_evaluation,
    )  # fmt: skip
    units = FaceUnits.of(description.model, description.params)
    uplink = ParameterDecoder(units, replace(context.stream, frames_per_packet=1))
    context.selected = {}
    return sender, uplink


def compute_uplink(memo: UplinkMemo, scenario, frames, *, width: int, height: int, fps: float):
    """Code `frames` as the sender would and decode them as the engine would, into `memo`
    (what a run of them then takes from it instead of coding)."""
    sender = SenderCoder(scenario, width=width, height=height, fps=fps, clock=CodecClock(False),
                         memo=memo)  # fmt: skip
    receiver = UplinkReceiver(video_class(uplink_name(), "video_decoder")(), memo)
    for frame in frames:
        receiver.decode(sender.encode(frame))
