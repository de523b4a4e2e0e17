"""The simulation's side of the codec registry (`uma.codecs`): the chain of a run's coders.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in pixels; bytes out.

`CodecChain` wires the three roles (`uma.sim.coders`: the sender's, the engine's and the
receiver's coders, each looking its classes up in the registry through
`uma.sim.coder_factories`) over one shared `CodecContext`, and the model-aided refresh's two
ends between the engine's and the receiver's; with an `UplinkMemo` (`uma.sim.uplink`) the
sender's stream and the engine's decode of it are taken from it where it has them. The world
and `uma bench sim` call it; the coders' factories are re-exported here.
"""

from __future__ import annotations

import numpy as np

from uma.codecs import model_names, spec
from uma.config.scenario import Scenario
from uma.engine.points import OperatingPoint
from uma.sim.coded import Coded
from uma.sim.coder_factories import (
    DECODERS,
    ENCODERS,
    FullFramePointEncoder,
    FullFrameUnitDecoder,
    decoder_factory,
    encoder_factory,
    video_class,
)
from uma.sim.coders import CodecClock, EngineCoder, ReceiverCoder, SenderCoder, selection_coders
from uma.sim.context import CodecContext
from uma.sim.mbc_codecs import MbcPointEncoder, MbcUnitDecoder, SelectedMbcEncoder, SenderMbc
from uma.sim.packets import EncodedUnit
from uma.sim.sent_view import SentView
from uma.sim.uplink import UplinkMemo

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


class CodecChain:
    """A run's coders: `sender`, `engine` and `receiver` (`uma.sim.coders`), one context."""

    def __init__(
        self, scenario: Scenario, ladder, points: tuple[OperatingPoint, ...], *, width: int,
        height: int, fps: float, account: bool = False, description=None,
        uplink: UplinkMemo | None = None,
    ) -> None:  # fmt: skip
        self.points, self.clock = points, CodecClock(account)
        section = getattr(scenario.engine, spec(model_names()[0]).config_section)
        self.context = CodecContext(
            description=description, seed=scenario.seed, source_size=(width, height),
            face_region=scenario.engine.face_region, fps=fps,
            **{spec(model_names()[0]).config_section: section},
        )  # fmt: skip
        self.refresh = None  # the model-aided refresh's two ends (`uma.sim.refresh`)
        if description is not None and section.refresh.enabled:
            from uma.sim.refresh import RefreshChain

            self.refresh = RefreshChain(section.refresh, source_size=(width, height))
        tracker = params = None
        if description is not None:
            from uma.mbc import StreamConfig

            self.context.stream = StreamConfig(
                frames_per_packet=section.frames_per_packet,
                intra_period_frames=section.intra_period_frames,
            )
            # The customisation scheme: `adaptation` (the engine tracks the face in the
            # picture it decodes) or `selection` (the sender tracks, and sends them up too).
            if section.scheme == "selection":
                tracker, params = selection_coders(self.context, description, section)
        size = {"width": width, "height": height, "fps": fps, "clock": self.clock}
        self.sender = SenderCoder(scenario, tracker=tracker, memo=uplink, **size)
        self.engine = EngineCoder(
            scenario, ladder, points, self.context, uplink_params=params, refresh=self.refresh,
            memo=uplink, **size,
        )  # fmt: skip
        self.receiver = ReceiverCoder(self.context, clock=self.clock, refresh=self.refresh)
        self.sent = SentView(self.context)  # what the engine knows the receiver decodes

    @property
    def seconds(self) -> float:
        return self.clock.seconds

    @property
    def codec_seconds(self) -> dict[str, float]:
        return self.clock.codec_seconds

    @property
    def engine_point(self) -> int:
        return self.engine.point

    def sender_encode(self, frame: np.ndarray):
        return self.sender.encode(frame)

    def sender_side_data(self, frame: np.ndarray, index: int) -> bytes | None:
        return self.sender.side_data(frame, index)

    def engine_receive_side(self, data: bytes | None, index: int) -> None:
        self.engine.receive_side(data, index)

    def engine_decode(self, encoded) -> np.ndarray | None:
        return self.engine.decode(encoded)

    def settings(self, codec: str):
        return self.engine.settings(codec)

    def initialise_model(self, picture: np.ndarray, index: int, *, frame: int):
        return self.engine.initialise_model(picture, index, frame=frame)

    def engine_encode(self, picture, index: int, *, force_idr: bool, frame: int = -1) -> Coded:
        return self.engine.encode(picture, index, force_idr=force_idr, frame=frame)

    def engine_flush(self) -> Coded | None:
        return self.engine.flush()

    def engine_released(self, unit: EncodedUnit) -> None:
        """A point's unit left the engine whole (its last packet offered to the downlink)."""
        self.sent.released(unit)

    def engine_refresh(self, picture: np.ndarray, order):
        """The refresh `order` of `picture` coded, judged against the picture the receiver's
        model codec started its stretch from, as the engine's released units decode (it
        cannot see the receiver's): (bytes, intra, gain_db), or None."""
        return self.engine.code_refresh(picture, order, self.sent.stretch_picture())

    def engine_discard_refresh(self, frame: int) -> None:
        self.engine.discard_refresh(frame)

    def engine_adopt_refresh(self, frame: int) -> None:
        self.engine.adopt_refresh(frame)

    def receiver_decode(self, unit: EncodedUnit) -> dict[int, np.ndarray]:
        return self.receiver.decode(unit)

    def receiver_refresh(self, unit: EncodedUnit) -> np.ndarray | None:
        return self.receiver.decode_refresh(unit)

    def receiver_refresh_frame(self) -> int:
        return self.receiver.refresh_frame()
