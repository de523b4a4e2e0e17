"""The model-aided refresh's coder and the receiver's composition: one place for both ends.

Units: pixels; pictures planar YUV 4:2:0 (H * 3 // 2, W) uint8; rates in kbit/s; bits.

What a refresh codes (chosen by measurement, docs/refresh.md): a box around the face (`margin`
times the model's extent on the first tracked frame, a multiple of 16 pixels), coded at
`scale` of its size by H.264 at a low frame rate, its corner on each coded frame (the face's
centre there) sent beside it in `POSITION_BITS`; or, for `region="frame"`, the whole picture at
a given coded size. The receiver takes a decoded refresh as its new reference
(`take_refresh`): the box pasted with a feathered edge onto its own rendering of that frame at
the pose the parameter stream decoded for it, the plate learning only the box's pixels. The
engine's mirror takes it the same way, so both ends render from the same picture.

A residual refresh (`RefreshCoder.code(..., base=)`) codes instead the source minus the
engine's rendering of that frame in the box (`base`: what the receiver will draw there, from
the reference it will hold when it takes the refresh), plus `RESIDUAL_OFFSET`, at the coded
size; the receiver adds the decoded residual (`ResidualBox`) to its own rendering of that frame
(`take_refresh`), so the rendering's detail stays where the residual is flat.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.mbc.errors import SceneError
from uma.mbc.layers import N_BODY, N_TORSO

__all__ = [
    "RefreshCoder",
    "RefreshUnitDecoder",
    "REFRESH_CODEC",
    "refresh_codec_classes",
    "face_box_size",
    "box_corner",
    "even_px",
    "take_refresh",
    "ResidualBox",
    "residual_patch",
    "POSITION_BITS",
    "RESIDUAL_OFFSET",
]

POSITION_BITS = 32  # a face box's position, two 16-bit numbers a unit
FEATHER_PX = 8
RESIDUAL_OFFSET = 128  # a residual's zero, in levels
RESIDUAL_DETAIL = 1.0  # how much of the rendering's detail finer than the coded size stays
# The least coded width and height by codec: SVT-AV1's rate control refuses pictures under
# 64 pixels a side ("Adaptive quantization can not be turned OFF when RC ON").
MIN_CODED_PX = {"av1": 64}
# The refresh's codec unless told: libx264 (SVT-AV1 and VP8 measured no better, docs/refresh.md).
REFRESH_CODEC = "h264"


@dataclass(frozen=True, eq=False)
class ResidualBox:
    """A decoded residual refresh: the box's corner (x0, y0) and size (W, H) in the picture,
    and the residual as decoded (YUV 4:2:0 at the coded size, `RESIDUAL_OFFSET` meaning no
    change)."""

    corner: tuple[int, int]
    box: tuple[int, int]
    residual: np.ndarray


def _residual(frame_low: np.ndarray, base_low: np.ndarray) -> np.ndarray:
    """`frame_low` - `base_low` + `RESIDUAL_OFFSET`, clipped to levels (YUV 4:2:0 alike)."""
    diff = frame_low.astype(np.int16) - base_low.astype(np.int16) + RESIDUAL_OFFSET
    return np.clip(diff, 0, 255).astype(np.uint8)


def residual_patch(base: np.ndarray, refresh: ResidualBox) -> np.ndarray:
    """The box the receiver composes from a decoded residual `refresh` on its own rendering
    `base` (YUV 4:2:0 at the source size): the rendering's box at the coded size plus the
    residual, back at the box's size, plus `RESIDUAL_DETAIL` times the rendering's detail
    finer than the coded size (YUV 4:2:0 at the box's size)."""
    from uma.video import resize_yuv420

    box_w, box_h = refresh.box
    coded_h, coded_w = refresh.residual.shape[0] * 2 // 3, refresh.residual.shape[1]
    base_box = _crop(base, *refresh.corner, box_w, box_h)
    base_low = resize_yuv420(base_box, coded_w, coded_h)
    low = base_low.astype(np.int16) + refresh.residual.astype(np.int16) - RESIDUAL_OFFSET
    patch = resize_yuv420(np.clip(low, 0, 255).astype(np.uint8), box_w, box_h)
    if RESIDUAL_DETAIL == 0.0 or base_low is base_box:
        return patch
    detail = base_box.astype(np.float32) - resize_yuv420(base_low, box_w, box_h)
    return np.clip(np.rint(patch + RESIDUAL_DETAIL * detail), 0, 255).astype(np.uint8)


def even_px(value: float) -> int:
    return max(2, int(round(value / 2)) * 2)


def face_box_size(model, params: np.ndarray, margin: float, size: tuple[int, int]):
    """The refresh box (W, H): `margin` x the model's extent at `params`, a multiple of 16
    pixels, within the picture of `size` (W, H)."""
    from uma.face.geometry import project

    extent = np.ptp(project(model, params), axis=0) * margin
    return tuple(
        min(int(np.ceil(v / 16)) * 16, limit) for v, limit in zip(extent, size, strict=True)
    )


def box_corner(model, params: np.ndarray, box: tuple[int, int], size: tuple[int, int]):
    """The box's even corner (x0, y0), centred on the face at `params`, inside the picture."""
    from uma.face.geometry import project

    (box_w, box_h), (width, height) = box, size
    centre = project(model, params).mean(axis=0)
    x0 = min(max(even_px(centre[0] - box_w / 2), 0), width - box_w)
    y0 = min(max(even_px(centre[1] - box_h / 2), 0), height - box_h)
    return x0, y0


def _crop(frame: np.ndarray, x0: int, y0: int, box_w: int, box_h: int) -> np.ndarray:
    """The box of a YUV 4:2:0 picture as a YUV 4:2:0 picture (corner and size even)."""
    from uma.video import split_planes

    y, u, v = split_planes(frame)
    out = np.empty((box_h * 3 // 2, box_w), np.uint8)
    out[:box_h] = y[y0 : y0 + box_h, x0 : x0 + box_w]
    chroma = out[box_h:].reshape(2, box_h // 2, box_w // 2)
    for plane, source in zip(chroma, (u, v), strict=True):
        plane[:] = source[y0 // 2 : (y0 + box_h) // 2, x0 // 2 : (x0 + box_w) // 2]
    return out


def _paste(canvas: np.ndarray, patch: np.ndarray, x0: int, y0: int) -> np.ndarray:
    """`canvas` (YUV 4:2:0) with `patch` (YUV 4:2:0) at (x0, y0), its edge feathered into it
    over `FEATHER_PX` so no seam shows where the older picture goes on."""
    height, width = canvas.shape[0] * 2 // 3, canvas.shape[1]
    box_h, box_w = patch.shape[0] * 2 // 3, patch.shape[1]

    def ramp(n: int) -> np.ndarray:
        k = np.arange(n, dtype=np.float32)
        return np.clip(np.minimum(k + 1, n - k) / FEATHER_PX, 0.0, 1.0)

    weight = np.outer(ramp(box_h), ramp(box_w))
    out = canvas.copy()
    luma = out[:height, x0 : x0 + box_w][y0 : y0 + box_h]
    luma[:] = np.rint(weight * patch[:box_h] + (1 - weight) * luma)
    half = weight[0::2, 0::2]
    chroma = out[height:].reshape(2, height // 2, width // 2)
    patch_chroma = patch[box_h:].reshape(2, box_h // 2, box_w // 2)
    for plane, source in zip(chroma, patch_chroma, strict=True):
        box = plane[y0 // 2 : y0 // 2 + box_h // 2, x0 // 2 : x0 // 2 + box_w // 2]
        box[:] = np.rint(half * source + (1 - half) * box)
    return out


def refresh_codec_classes(codec: str):
    """The (encoder, decoder) classes of `uma.video` a refresh codes with, by the codec
    registry's full-frame name (`h264`, `vp8`, `av1`); a `SceneError` naming the known ones
    otherwise."""
    import uma.video
    from uma.codecs import Role, names, spec

    known = names(Role.FULL_FRAME)
    if codec not in known:
        raise SceneError(f"refresh codec: expected one of {', '.join(known)}, got {codec!r}")
    entry = spec(codec)
    return getattr(uma.video, entry.video_encoder), getattr(uma.video, entry.video_decoder)


class RefreshCoder:
    """The engine's refresh coder and its decoded picture: `codec` (a full-frame codec of the
    registry, its encoder at `settings`, e.g. its ladder's) of the face box of `box` (W, H)
    coded at `coded` (W, H), or of the whole picture at `coded` when `box` is None, at `fps`
    and `rate_kbps`. `close` ends the encoder (keep at most one SVT-AV1 encoder open)."""

    def __init__(
        self, size, coded, fps: float, rate_kbps: float, settings: dict, box=None,
        codec: str = REFRESH_CODEC,
    ):  # fmt: skip
        encoder_class, decoder_class = refresh_codec_classes(codec)
        least = MIN_CODED_PX.get(codec, 2)
        coded = tuple(max(int(v), least) for v in coded)
        self.size, self.coded, self.box, self.codec = tuple(size), coded, box, codec
        self.encoder = encoder_class(*self.coded, fps, rate_kbps, **settings)
        self.decoder = decoder_class()
        self.data = b""  # the last unit's bytes (a simulation carries them)

    def close(self) -> None:
        """Flush and end the encoder now (not at garbage collection)."""
        self.encoder.close()

    def code(self, frame: np.ndarray, corner=None, base: np.ndarray | None = None):
        """`frame` (YUV 4:2:0, source size) coded: (size in bits with the box's position,
        keyframe, what the receiver decodes: the whole picture at the source size, or (corner,
        box picture), or a `ResidualBox` when `base` (the engine's rendering of that frame,
        YUV 4:2:0 at the source size) is given, or None)."""
        from uma.video import resize_yuv420

        extra_bits = 0
        if self.box is not None:
            frame, extra_bits = _crop(frame, *corner, *self.box), POSITION_BITS
        elif base is not None:
            raise SceneError("refresh: a residual needs a face box, got the whole picture")
        frame = resize_yuv420(frame, *self.coded)
        if base is not None:
            frame = _residual(frame, resize_yuv420(_crop(base, *corner, *self.box), *self.coded))
        unit = self.encoder.encode(frame)
        self.data = unit.data
        picture = self.decoder.decode(unit.data)
        picture = _received(picture, self.size, self.box, corner, base is not None)
        return unit.size_bits + extra_bits, bool(unit.is_keyframe), picture

    def receiver(self) -> RefreshUnitDecoder:
        """A receiver's own decoder of this coder's units."""
        return RefreshUnitDecoder(self.size, self.box, self.codec)


class RefreshUnitDecoder:
    """A receiver's decoder of a `RefreshCoder`'s units (its own codec's decoder): a unit's
    bytes, in sending order, to the picture the coder's `code` gave for it, from the bytes
    and, for a face box, the corner sent beside them."""

    def __init__(self, size, box=None, codec: str = REFRESH_CODEC) -> None:
        self.size, self.box = tuple(size), box
        self.decoder = refresh_codec_classes(codec)[1]()

    def decode(self, data: bytes, corner=None, residual: bool = False):
        """The unit `data` decoded: the whole picture at the source size, (corner, box
        picture), a `ResidualBox` when `residual`, or None."""
        return _received(self.decoder.decode(data), self.size, self.box, corner, residual)


def _received(picture, size, box, corner, residual: bool):
    """A decoded unit as the receiver takes it (see `RefreshCoder.code`); None stays None."""
    from uma.video import resize_yuv420

    if picture is None:
        return None
    if box is None:
        return resize_yuv420(picture, *size)
    if residual:
        return ResidualBox(tuple(corner), box, picture)
    return (tuple(corner), resize_yuv420(picture, *box))


def _box_of(patch) -> tuple[int, int]:
    """A decoded box's (H, W); a `SceneError` naming what it is when it is not a YUV 4:2:0
    uint8 picture of even size (it cannot be pasted on the plate)."""
    patch = np.asarray(patch)
    rows = patch.shape[0] if patch.ndim == 2 else 0
    if patch.ndim != 2 or patch.dtype != np.uint8 or rows % 3 or patch.shape[1] % 2 or not rows:
        raise SceneError(
            f"refresh box: expected a YUV 4:2:0 uint8 picture of even size, got "
            f"{patch.shape} {patch.dtype}"
        )
    return rows * 2 // 3, patch.shape[1]


def take_refresh(renderer, units, values: np.ndarray, picture) -> None:
    """`renderer` (a `uma.mbc.scene_render.SceneRenderer`) renders from the decoded refresh
    `picture` (`RefreshCoder.code`'s) from now on, at the decoded set `values` of its frame
    (`units`, `uma.mbc.units.FaceUnits`, split it): a box is pasted onto the renderer's own
    picture of that frame first, and only its pixels teach the plate. A `SceneError` when it
    cannot (the old reference stays). A `ResidualBox` is added to the renderer's own
    picture of that frame in its box first. A set carrying the camera's motion moves the plate
    by it first (`SceneRenderer.set_reference`'s `camera`)."""
    params, light = units.split(values)
    height, width = renderer.size[1], renderer.size[0]
    body = units.body_of(values)
    camera = None if body is None or len(body) < N_BODY else body[N_TORSO:]
    fresh = None
    if isinstance(picture, (tuple, ResidualBox)):
        residual = isinstance(picture, ResidualBox)
        if residual:
            (x0, y0), (box_w, box_h), patch = picture.corner, picture.box, None
        else:
            (x0, y0), patch = picture
            box_h, box_w = _box_of(patch)
        if x0 < 0 or y0 < 0 or x0 + box_w > width or y0 + box_h > height:
            raise SceneError(f"refresh box at ({x0}, {y0}) of {box_w}x{box_h}: outside the picture")
        drawn = renderer.render(params, light, body)[0]
        if residual:
            patch = residual_patch(drawn, picture)
        picture = _paste(drawn, patch, x0, y0)
        fresh = np.zeros((height, width), bool)
        fresh[y0 : y0 + box_h, x0 : x0 + box_w] = True
    renderer.set_reference(picture, params, fresh, camera)
