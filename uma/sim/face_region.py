"""The face-region H.264 rung (`h264-face`): code only the face box, composite it at the receiver.

Units: pixels; pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; rates in kbit/s.

Object-level adaptation, between full-frame H.264 and the model-based codec. The engine's
encoder finds the face in its decoded picture (OpenCV's Haar cascade, `uma.face.detect`, on the
picture scaled to at most `DETECT_WIDTH` pixels wide), on a rung's first frame and then every
`detect_every_frames` source frames, and smooths the box centre between detections. The crop
is the first box found, widened by `margin` a side and shaped like the rung's coded size; its
size stays fixed for the stream (a zoom would defeat motion prediction), its position follows
the face, on even pixels so the chroma planes crop with it. The crop is scaled to the rung's
coded size and coded with libx264, so the H.264 stream keeps one size. Each unit is `HEADER`
(the crop box in source pixels: x, y, width, height as big-endian uint16) then the access unit;
the header's bits count with the unit's. The receiver decodes the crop, scales it back to the
box and pastes it, chroma included, over the last picture it showed before the switch (at the
source's size), which stays the background for as long as the rung lasts.
"""

from __future__ import annotations

import struct

import numpy as np

from uma.engine.points import OperatingPoint
from uma.face.detect import Box
from uma.sim.coded import Coded
from uma.sim.context import as_context
from uma.sim.packets import EncodedUnit

__all__ = [
    "FaceRegionEncoder",
    "FaceRegionDecoder",
    "HEADER",
    "crop_box",
    "crop_yuv420",
    "paste_yuv420",
    "detect_box",
    "DETECT_WIDTH",
]

HEADER = struct.Struct(">4H")  # crop x, y, width, height in source pixels
DETECT_WIDTH = 176  # the detector scans the picture scaled to at most this width (QCIF)


def _even(value: float) -> int:
    return int(round(value / 2.0)) * 2


def crop_box(
    face: Box,
    centre: tuple[float, float],
    *,
    coded: tuple[int, int],
    source: tuple[int, int],
    margin: float,
    size: tuple[int, int] | None = None,
) -> Box:
    """The crop around `centre`: `size` (or `face` widened by `margin` a side, shaped like
    `coded`), even, inside the `source` frame."""
    width, height = source
    if size is None:
        aspect = coded[0] / coded[1]
        side_w = max(face.width, face.height * aspect) * (1.0 + 2.0 * margin)
        size = (_even(side_w), _even(side_w / aspect))
    crop_w = max(2, min(size[0], width - width % 2))
    crop_h = max(2, min(size[1], height - height % 2))
    x = min(max(0, _even(centre[0] - crop_w / 2.0)), width - crop_w)
    y = min(max(0, _even(centre[1] - crop_h / 2.0)), height - crop_h)
    return Box(x - x % 2, y - y % 2, crop_w, crop_h)


def crop_yuv420(picture: np.ndarray, box: Box) -> np.ndarray:
    """The YUV 4:2:0 picture inside `box` (even position and size)."""
    from uma.video import split_planes

    y, u, v = split_planes(picture)
    out = np.empty((box.height * 3 // 2, box.width), dtype=np.uint8)
    out[: box.height] = y[box.y : box.y + box.height, box.x : box.x + box.width]
    chroma = out[box.height :].reshape(2, box.height // 2, box.width // 2)
    cx, cy, cw, ch = box.x // 2, box.y // 2, box.width // 2, box.height // 2
    chroma[0] = u[cy : cy + ch, cx : cx + cw]
    chroma[1] = v[cy : cy + ch, cx : cx + cw]
    return out


def paste_yuv420(background: np.ndarray, patch: np.ndarray, box: Box) -> np.ndarray:
    """A copy of `background` with `patch` (YUV 4:2:0 of `box`'s size) pasted at `box`."""
    from uma.video import split_planes

    out = background.copy()
    y, u, v = split_planes(out)
    py, pu, pv = split_planes(patch)
    y[box.y : box.y + box.height, box.x : box.x + box.width] = py
    cx, cy, cw, ch = box.x // 2, box.y // 2, box.width // 2, box.height // 2
    u[cy : cy + ch, cx : cx + cw] = pu
    v[cy : cy + ch, cx : cx + cw] = pv
    return out


def detect_box(picture: np.ndarray) -> Box | None:
    """The face in a YUV 4:2:0 picture, found on its luma scaled to at most `DETECT_WIDTH`
    wide (the cascade's cost grows with the pixels it scans), in source pixels; or None."""
    import cv2

    from uma.face.detect import detect_face

    height = picture.shape[0] * 2 // 3
    luma = np.ascontiguousarray(picture[:height])
    factor = max(1, -(-luma.shape[1] // DETECT_WIDTH))
    if factor > 1:
        size = (luma.shape[1] // factor, height // factor)
        luma = cv2.resize(luma, size, interpolation=cv2.INTER_AREA)
    found = detect_face(luma)
    if not found:
        return None
    return Box(found.x * factor, found.y * factor, found.width * factor, found.height * factor)


def detect_pixels(source_size: tuple[int, int]) -> int:
    """Pixels the detector scans for a picture of `source_size`."""
    width, height = source_size
    factor = max(1, -(-width // DETECT_WIDTH))
    return (width // factor) * (height // factor)


class FaceRegionEncoder:
    """libx264 on the face crop at one `h264-face` point; `evaluations` counts detector runs.

    Context (`uma.sim.context.CodecContext`): `face_region`, the scenario's `FaceRegionConfig`.
    """

    def __init__(self, point: OperatingPoint, *, source_size, source_fps, settings, context):
        from uma.video import H264Encoder

        config = as_context(context).face_region
        self.margin = config.margin
        self.every = config.detect_every_frames
        self.smoothing = config.smoothing
        self.source = tuple(source_size)
        self.width, self.height = point.width, point.height
        fps = min(point.fps, source_fps)
        # The header rides in every unit: libx264 gets the rest of the point's rate.
        header_kbps = 8 * HEADER.size * fps / 1000.0
        self.encoder = H264Encoder(
            self.width,
            self.height,
            fps,
            max(1.0, point.rate_kbps - header_kbps),
            **settings.kwargs(),
        )
        self.size: tuple[int, int] | None = None  # the crop's size, fixed at the first face
        self.centre: tuple[float, float] | None = None
        self.face: Box | None = None
        self.last_detect = -(10**9)
        self.misses = 0

    def _detect(self, picture: np.ndarray, frame: int) -> bool:
        """Run the detector when due; False when there is no face to code."""
        if frame >= 0 and frame - self.last_detect < self.every and self.face is not None:
            return True
        self.last_detect = frame
        found = detect_box(picture)
        if found is None:
            self.misses += 1
            # A missed detection keeps the last box; three in a row mean the face is gone.
            return self.face is not None and self.misses < 3
        self.misses = 0
        centre = found.centre
        if self.centre is not None:
            a = self.smoothing
            centre = (
                self.centre[0] + a * (centre[0] - self.centre[0]),
                self.centre[1] + a * (centre[1] - self.centre[1]),
            )
        self.face, self.centre = found, centre
        return True

    def encode(self, picture: np.ndarray, *, intra: bool, frame: int = -1) -> Coded:
        from uma.video import resize_yuv420

        before = self.last_detect
        ok = self._detect(picture, frame)
        detections = int(self.last_detect != before)
        if not ok:
            return Coded(
                b"", False, self.width, self.height, detections, failure="no face detected"
            )
        box = crop_box(
            self.face,
            self.centre,
            coded=(self.width, self.height),
            source=self.source,
            margin=self.margin,
            size=self.size,
        )
        self.size = (box.width, box.height)
        crop = resize_yuv420(crop_yuv420(picture, box), self.width, self.height)
        out = self.encoder.encode(crop, force_idr=intra)
        data = HEADER.pack(box.x, box.y, box.width, box.height) + out.data
        return Coded(data, bool(out.is_keyframe), self.width, self.height, detections)


class FaceRegionDecoder:
    """Decodes the crop and composites it over the picture shown before the switch."""

    def __init__(self, *, context) -> None:
        from uma.video import H264Decoder, resize_yuv420

        context = as_context(context)
        width, height = context.source_size
        self.decoder = H264Decoder()
        background = context.background
        if background is None:
            # Nothing shown yet: mid-grey around the face.
            background = np.full((height * 3 // 2, width), 128, dtype=np.uint8)
        self.background = np.ascontiguousarray(resize_yuv420(background, width, height))
        self.source = (width, height)

    def decode(self, unit: EncodedUnit) -> dict[int, np.ndarray]:
        from uma.errors import VideoError
        from uma.video import resize_yuv420

        if len(unit.data) <= HEADER.size:
            return {}
        x, y, w, h = HEADER.unpack_from(unit.data)
        width, height = self.source
        if w < 2 or h < 2 or w % 2 or h % 2 or x % 2 or y % 2 or x + w > width or y + h > height:
            return {}  # a damaged header: the chain breaks, the receiver asks for a keyframe
        try:
            picture = self.decoder.decode(unit.data[HEADER.size :])
        except VideoError:
            return {}
        if picture is None:
            return {}
        patch = resize_yuv420(picture, w, h)
        return {unit.frame: paste_yuv420(self.background, patch, Box(x, y, w, h))}
