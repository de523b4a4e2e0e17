"""The engine's own view of the picture the receiver's model codec draws over.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8.

The receiver's model codec starts from the last picture it decoded before the model codec's
first unit (`ReceiverCoder.decode`). The engine cannot look at the receiver; what it knows is
the units it released to the downlink. `SentView` keeps them, from the last full-frame keyframe
on, and when the model codec's first unit leaves it keeps that chain: asked for the picture,
it decodes the chain once with decoders of its own (the registry's, on its own copy of the
codec context), as if every unit arrived. Where the downlink lost one, the receiver's picture
differs from this one, as a real engine's would.
"""

from __future__ import annotations

import copy

import numpy as np

from uma.codecs import Role, spec
from uma.sim.coders import CodecClock, ReceiverCoder
from uma.sim.packets import EncodedUnit

__all__ = ["SentView"]


class SentView:
    """The units the engine released, and the picture they decode to before a model stretch."""

    def __init__(self, context) -> None:
        self._context = context
        self._chain: list[EncodedUnit] = []  # non-model units since the last full-frame keyframe
        self._stretch: list[EncodedUnit] | None = None  # the chain as the model codec began
        self._picture: np.ndarray | None = None
        self._decoded = False

    def released(self, unit: EncodedUnit) -> None:
        """`unit` (a point's, not a refresh's) left the engine whole."""
        role = spec(unit.codec).role
        if role is Role.MODEL:
            if self._stretch is None:
                self._stretch, self._picture, self._decoded = list(self._chain), None, False
            return
        self._stretch = None
        if unit.keyframe and role is Role.FULL_FRAME:
            self._chain = []
        self._chain.append(unit)

    def stretch_picture(self) -> np.ndarray | None:
        """The picture the model codec's stretch started from, as the engine's units decode
        (None: not on the model codec, or nothing decoded before it)."""
        if self._stretch is None:
            return None
        if not self._decoded:
            context = copy.copy(self._context)
            context.background = None
            mirror = ReceiverCoder(context, clock=CodecClock(False))
            for unit in self._stretch:
                mirror.decode(unit)
            self._picture, self._decoded = mirror.last, True
        return self._picture
