"""The real codec work of a run, in one place: sender encode, engine decode and re-encode,
receiver decode (libx264 and FFmpeg through PyAV), with optional wall-clock accounting for
`uma bench sim` (the accounting never feeds back into the simulation).
"""

from __future__ import annotations

import time

import numpy as np

from uma.config.scenario import Scenario
from uma.sim.packets import EncodedUnit

__all__ = ["CodecChain"]


class CodecChain:
    """Encoders and decoders along the path; one engine encoder per rung, made on a switch."""

    def __init__(
        self,
        scenario: Scenario,
        ladder,
        *,
        width: int,
        height: int,
        fps: float,
        account: bool = False,
    ) -> None:
        from uma.video import H264Decoder, H264Encoder

        self._encoder_cls = H264Encoder
        self.scenario = scenario
        self.ladder = ladder
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
        self.receiver_decoder = H264Decoder()
        self.engine_encoder = None
        self.engine_rung = -1
        self.account = account
        self.seconds = 0.0

    def _timed(self, fn, *args, **kwargs):
        if not self.account:
            return fn(*args, **kwargs)
        start = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            self.seconds += time.perf_counter() - start

    def sender_encode(self, frame: np.ndarray):
        return self._timed(self.sender_encoder.encode, frame)

    def engine_decode(self, encoded) -> np.ndarray | None:
        return self._timed(self.engine_decoder.decode, encoded.data)

    def rung_size(self, rung_index: int) -> tuple[int, int]:
        """The rung's picture size, never larger than the source's (upscaling adds only bits)."""
        rung = self.ladder.rungs[rung_index]
        return min(rung.width, self.width), min(rung.height, self.height)

    def engine_encode(self, picture: np.ndarray, rung_index: int, *, force_idr: bool):
        return self._timed(self._engine_encode, picture, rung_index, force_idr)

    def _engine_encode(self, picture: np.ndarray, rung_index: int, force_idr: bool):
        from uma.video import resize_yuv420

        rung = self.ladder.rungs[rung_index]
        width, height = self.rung_size(rung_index)
        if rung_index != self.engine_rung:
            # A new rung is a new stream: new size and rate, starting with an IDR.
            self.engine_encoder = self._encoder_cls(
                width,
                height,
                min(rung.fps, self.fps),
                rung.rate_kbps,
                **self.ladder.encoder.kwargs(),
            )
            self.engine_rung = rung_index
            force_idr = True
        if (picture.shape[1], picture.shape[0] * 2 // 3) != (width, height):
            picture = resize_yuv420(picture, width, height)
        return self.engine_encoder.encode(picture, force_idr=force_idr)

    def receiver_decode(self, unit: EncodedUnit) -> np.ndarray | None:
        from uma.errors import VideoError

        try:
            return self._timed(self.receiver_decoder.decode, unit.data)
        except VideoError:
            return None
