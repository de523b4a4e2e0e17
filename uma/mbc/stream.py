"""The sending side of the parameter stream: quantise, predict, group into packets, code.

Units: parameters as in `uma.face.geometry` in, face animation units inside; frames count
source frames; bytes out.

`push(frame, params)` quantises a frame's parameters (intra, or residual to the previous
decoded values) at once, so the reference is what the decoder will hold; every
`frames_per_packet` frames the pending sets are range-coded into one packet. A packet starts
intra when the intra period is due, after `request_intra()` (the receiver's request), after a
frame without parameters (`push(frame, None)`: the tracker failed; the open packet is sent
short and the next set is intra), and on the first frame. Intra sets only open packets, so a
decoder can join at any intra packet. With `map_blocks` > 0 (the block map's window, `uma.mbc.block_map`) each set
carries its frame's block map changes (`push(frame, params, changes)`) in the same packet; a
packet none of whose frames changes the map goes without them (its flag clear: no bit spent).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.mbc.coding import AdaptiveModels, CoderConfig, encode_sets
from uma.mbc.packets import SEQ_MODULUS, Packet
from uma.mbc.quant import Quantiser, QuantiserConfig
from uma.mbc.units import FaceUnits

__all__ = ["StreamConfig", "ParameterEncoder"]


@dataclass(frozen=True)
class StreamConfig:
    """How parameters travel. `frames_per_packet` trades header overhead for delay (see the
    README: 4 frames keep the wire rate under 4.8 kbit/s and add 120 ms at 25 frames/s);
    `intra_period_frames` bounds how long a decoder waits after a loss."""

    quantiser: QuantiserConfig = QuantiserConfig()
    coder: CoderConfig = CoderConfig()
    frames_per_packet: int = 4
    intra_period_frames: int = 96

    def __post_init__(self) -> None:
        if not 1 <= self.frames_per_packet <= 255:
            raise ValueError(f"stream: frames_per_packet 1-255, got {self.frames_per_packet}")
        if self.intra_period_frames < self.frames_per_packet:
            raise ValueError(
                f"stream: intra_period_frames ({self.intra_period_frames}) below "
                f"frames_per_packet ({self.frames_per_packet})"
            )


class ParameterEncoder:
    """Parameters in, packets out; the decoder (`uma.mbc.decoder.ParameterDecoder`) mirrors it."""

    def __init__(self, units: FaceUnits, config: StreamConfig = StreamConfig(), map_blocks=0):
        self.units = units
        self.config = config
        self.map_blocks = int(map_blocks)
        self.quantiser = Quantiser(units.kinds, config.quantiser)
        self.models = AdaptiveModels(units.unit.size, config.coder)
        self._seq = 0
        self._pending: list[tuple] = []  # (intra, indices, block map changes)
        self._first = 0
        self._next = None  # the frame expected next
        self._reference: np.ndarray | None = None  # decoded values (face animation units)
        self._intra_due = True
        self._since_intra = 0
        self.decoded: np.ndarray | None = None  # the last set as the decoder will see it

    def request_intra(self) -> None:
        """The next packet starts with an intra set."""
        self._intra_due = True

    def push(self, frame: int, params: np.ndarray | None, changes=None) -> list[Packet]:
        """Add one frame's parameters (None: the tracker has none) and its block map `changes`
        ((n, 2): block index, choice code; None: none; a callable: called with the set as
        the decoder will see it, returns them); returns finished packets."""
        out: list[Packet] = []
        if params is None or (self._next is not None and frame != self._next):
            out += self.flush()
            self._intra_due = True
            self._reference = None
            self._next = None if params is None else frame
            if params is None:
                return out
        params = np.asarray(params, dtype=np.float64)
        if params.shape != self.units.unit.shape or not np.all(np.isfinite(params)):
            raise ValueError(
                f"frame {frame}: expected {self.units.unit.size} finite parameters, got "
                f"{params.shape}"
            )
        values = self.units.to_units(params)
        code = self.config.quantiser.global_code
        if not self._pending:
            self._first = frame
            if self._intra_due or self._since_intra >= self.config.intra_period_frames:
                self._intra_due = False
                self._since_intra = 0
                self._reference = None
        if self._reference is None:
            indices = self.quantiser.intra(values, code)
            self._reference = self.quantiser.dequantise_intra(indices, code)
            intra = True
        else:
            indices = self.quantiser.predict(values, self._reference, code)
            self._reference = self.quantiser.dequantise_predictive(indices, self._reference, code)
            intra = False
        self.decoded = self.units.from_units(self._reference)
        self._pending.append(
            (intra, indices, changes(self.decoded) if callable(changes) else changes)
        )
        self._since_intra += 1
        self._next = frame + 1
        if len(self._pending) >= self.config.frames_per_packet:
            out += self.flush()
        return out

    def flush(self) -> list[Packet]:
        """The open packet, even if short."""
        if not self._pending:
            return []
        with_map = self.map_blocks > 0 and any(
            changes is not None and len(changes) for _, _, changes in self._pending
        )
        words, _ = encode_sets(self._pending, self.models, self.map_blocks if with_map else 0)
        packet = Packet(
            seq=self._seq,
            first_frame=self._first,
            count=len(self._pending),
            intra=self._pending[0][0],
            global_code=self.config.quantiser.global_code,
            words=words,
            light=self.units.light,
            body=self.units.body,
            camera=self.units.camera,
            block_map=with_map,
        )
        self._seq = (self._seq + 1) % SEQ_MODULUS
        self._pending = []
        return [packet]
