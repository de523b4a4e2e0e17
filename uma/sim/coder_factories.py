"""Each registered codec's coders in the simulation, made from its registry entry.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in pixels; bytes out.

Every engine-side encoder has `encode(picture, *, intra, frame) -> Coded` (bytes and what it
cost, in fitting-cost evaluations, so the engine can model compute time); every receiver-side
decoder has `decode(unit) -> {frame: picture}`. `ENCODERS` and `DECODERS` map every registered
codec name to a factory: a full-frame codec's are made from the `uma.video` classes its
registry entry names (`video_class`), the region and model codecs' are their own modules'.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np

from uma.codecs import REGISTRY, Role, full_frame_names, spec
from uma.engine.points import OperatingPoint
from uma.sim.coded import Coded
from uma.sim.face_region import FaceRegionDecoder, FaceRegionEncoder
from uma.sim.mbc_codecs import MbcPointEncoder, MbcUnitDecoder, SelectedMbcEncoder
from uma.sim.packets import EncodedUnit

__all__ = [
    "FullFramePointEncoder",
    "FullFrameUnitDecoder",
    "video_class",
    "encoder_factory",
    "decoder_factory",
    "ENCODERS",
    "DECODERS",
]


class FullFramePointEncoder:
    """A full-frame codec at one operating point: its rate, size (never above the source's)
    and frame rate, coded by the `uma.video` class its registry entry names.

    `span`: (fps, max_rate_kbps) of every point of its size (`Ladder.open_span`): an encoder
    that can be retargeted (`retargets`: H.264, opened with `max_rate_kbps`) opens so that `retarget` reaches each of
    them without a keyframe; one that cannot opens at the point as before."""

    def __init__(
        self, point: OperatingPoint, *, source_size, source_fps, settings, context=None,
        span: tuple[float, float] | None = None,
    ) -> None:  # fmt: skip
        self.width = min(point.width, source_size[0])
        self.height = min(point.height, source_size[1])
        self.source_fps = source_fps
        cls = video_class(point.codec, "video_encoder")
        fps = min(point.fps, source_fps)
        if span is None or not cls.retargets:
            self.encoder = cls(self.width, self.height, fps, point.rate_kbps, **settings.kwargs())
            return
        span_fps = min(span[0], source_fps)
        self.encoder = cls(
            self.width, self.height, span_fps, point.rate_kbps * span_fps / fps,
            max_rate_kbps=max(span[1], point.rate_kbps * span_fps / fps), **settings.kwargs(),
        )  # fmt: skip
        self.encoder.set_target(point.rate_kbps, fps)

    def retarget(self, point: OperatingPoint) -> bool:
        """Aim the open encoder at `point` (same size) from the next frame, no keyframe;
        False when it cannot (a new encoder is needed)."""
        fps = min(point.fps, self.source_fps)
        return bool(self.encoder.set_target(point.rate_kbps, fps))

    def encode(self, picture: np.ndarray, *, intra: bool, frame: int = -1) -> Coded:
        from uma.video import resize_yuv420

        if (picture.shape[1], picture.shape[0] * 2 // 3) != (self.width, self.height):
            picture = resize_yuv420(picture, self.width, self.height)
        out = self.encoder.encode(picture, force_idr=intra)
        return Coded(out.data, bool(out.is_keyframe), self.width, self.height)


class FullFrameUnitDecoder:
    """A full-frame codec's decoder: {frame: picture}, or {} for a unit it cannot decode."""

    def __init__(self, *, context=None, codec: str = full_frame_names()[0]) -> None:
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
