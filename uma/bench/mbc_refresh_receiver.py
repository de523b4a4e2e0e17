"""`uma bench mbc`'s refresh receiver: it decodes the refresh units it receives with its own
decoder, takes the ones the engine's schedule says, and draws every decoded set with the
stream's block map changes.

Units: frames (indices into the clip), seconds.
"""

from __future__ import annotations

import time

import numpy as np

from uma.mbc.refresh_coder import RefreshCoder, take_refresh

__all__ = ["UnitsIn", "receive"]


class UnitsIn:
    """The receiver's refresh stream: every unit decoded by its own decoder once it has
    arrived (`arrived[k]`, the first frame unit k serves; -1 never), in sending order."""

    def __init__(
        self, coder: RefreshCoder | None, sent: list[tuple[bytes, object]], arrived, residual: bool
    ) -> None:
        self.decoder = coder.receiver() if coder is not None else None
        self.sent, self.arrived, self.residual = sent, arrived, residual
        self.pictures: dict[int, object] = {}

    def decode(self, index: int) -> None:
        """Decode every unit that has arrived by frame `index` and is not decoded yet."""
        k = len(self.pictures)
        while k < len(self.sent) and 0 <= self.arrived[k] <= index:
            data, corner = self.sent[k]
            self.pictures[k] = self.decoder.decode(data, corner, self.residual)
            k += 1


def receive(
    receiver, face_units, first: np.ndarray, count: int, engine, units_in: UnitsIn
) -> tuple[list[np.ndarray], float, float]:
    """The receiver's display of every frame (the last picture held where no set was decoded,
    `first` before any): each decoded set of `engine` (`uma.bench.mbc_refresh_engine.Engine`)
    drawn and its block map changes taken (as the simulation's `MbcUnitDecoder`); and the
    seconds (wall, CPU) it spent decoding and taking refreshes."""
    from uma.bench.mbc_stages import SCALED_FPS
    from uma.mbc.block_map import BlockMap

    block_map = BlockMap(receiver.size, SCALED_FPS)  # the engine's map's rates: 25 frames/s
    shown, last, switch_s, switch_cpu_s = [], first, 0.0, 0.0
    for index in range(count):
        begin, cpu = time.perf_counter(), time.process_time()
        units_in.decode(index)
        for k, values in engine.switches.get(index, ()):
            take_refresh(receiver, face_units, values, units_in.pictures[k])
        switch_s += time.perf_counter() - begin
        switch_cpu_s += time.process_time() - cpu
        if index in engine.decoded:
            values = engine.decoded[index]
            params, light = face_units.split(values)
            drawn, face = receiver.render(params, light, face_units.body_of(values))
            last = block_map.step_with(receiver, drawn, face, changes=engine.changes.get(index))
        shown.append(last)
    return shown, switch_s, switch_cpu_s
