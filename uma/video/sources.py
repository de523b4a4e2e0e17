"""Frame sources: a video file (anything PyAV decodes), raw YUV 4:2:0, a synthetic pattern.

Every source has `name`, `width`, `height`, `fps`, `frame_count` (None when unknown or endless)
and `frames()`, an iterator of planar YUV 4:2:0 arrays of shape (H * 3 // 2, W), uint8. With
`loop=True` a short clip repeats, so it can feed a long simulation.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from uma.errors import VideoError
from uma.paths import check_regular_file

__all__ = ["VideoFileSource", "RawYuvSource", "PatternSource"]

# A looped clip's decoded pictures are kept and replayed when they fit in this many bytes (akiyo
# at CIF: 300 frames, 46 MB); a longer clip is decoded again on each pass.
LOOP_KEEP_BYTES = 256 * 1024 * 1024


class VideoFileSource:
    """Frames decoded from a file by PyAV (any container and codec it reads).

    Pictures in another pixel format are converted to YUV 4:2:0; an odd width or height is
    cropped by one pixel to even. `frame_count` is the number of frames `frames()` yields (the
    container's count, capped by `max_frames`), None when endless (`loop` without `max_frames`)
    or when the container does not say.
    """

    def __init__(
        self, path: str | os.PathLike, *, loop: bool = False, max_frames: int | None = None
    ):
        import av

        self.path = Path(path)
        self.loop = loop
        self.max_frames = max_frames
        self.name = self.path.name
        if max_frames is not None and max_frames < 1:
            raise VideoError(
                f"{self.path}: max_frames: expected a positive integer, got {max_frames}"
            )
        check_regular_file(self.path, error=VideoError, what="video file")  # a FIFO, a folder
        try:
            with av.open(str(self.path)) as container:
                if not container.streams.video:
                    raise VideoError(f"{self.path}: the file holds no video stream")
                stream = container.streams.video[0]
                rate = stream.average_rate or stream.guessed_rate
                first = next(container.decode(stream), None)
                clip_frames = stream.frames or None
        except av.FFmpegError as err:
            raise VideoError(f"{self.path}: cannot open or decode as video ({err})") from None
        if first is None:
            raise VideoError(f"{self.path}: the video stream holds no decodable frame")
        self.fps = float(rate) if rate else 25.0
        self.width = first.width - first.width % 2
        self.height = first.height - first.height % 2
        if self.width < 2 or self.height < 2:
            raise VideoError(f"{self.path}: picture {first.width}x{first.height} is too small")
        self.clip_frames = clip_frames
        if loop:
            self.frame_count = max_frames
        elif max_frames is not None and clip_frames is not None:
            self.frame_count = min(max_frames, clip_frames)
        else:
            self.frame_count = clip_frames

    def _once(self) -> Iterator[np.ndarray]:
        import av

        index = 0
        try:
            with av.open(str(self.path)) as container:
                stream = container.streams.video[0]
                stream.thread_type = "AUTO"  # a file has no latency budget: decode on all cores
                for frame in container.decode(stream):
                    yield _to_yuv420(frame, self.width, self.height, self.path, index)
                    index += 1
        except av.FFmpegError as err:
            raise VideoError(f"{self.path}: decoding failed after {index} frames ({err})") from None

    def frames(self) -> Iterator[np.ndarray]:
        """The clip's pictures; with `loop`, the first pass is kept (when it fits in
        `LOOP_KEEP_BYTES`) and replayed as copies instead of decoding the file again."""
        produced = 0
        kept: list[np.ndarray] | None = [] if self.loop else None
        while True:
            empty = True
            for array in self._pass(kept):
                empty = False
                yield array
                produced += 1
                if self.max_frames is not None and produced >= self.max_frames:
                    return
            if not self.loop or empty:
                return
            if kept is not None and len(kept) == 0:
                kept = None  # the clip did not fit: decode each pass

    def _pass(self, kept: list[np.ndarray] | None) -> Iterator[np.ndarray]:
        """One pass over the clip: decoded (filling `kept` while it fits) or replayed."""
        if kept:
            for array in kept:
                yield array.copy()
            return
        frame_bytes = self.width * self.height * 3 // 2
        for array in self._once():
            if kept is not None:
                if (len(kept) + 1) * frame_bytes <= LOOP_KEEP_BYTES:
                    kept.append(array.copy())
                else:
                    kept.clear()
                    kept = None
            yield array


def _to_yuv420(frame, width: int, height: int, path: Path, index: int) -> np.ndarray:
    """A decoded picture as a (height * 3 // 2, width) YUV 4:2:0 array, cropped to that size,
    in limited range (luma 16-235, as the codecs and `uma.face.colour` take it): full-range
    pictures (MJPEG's yuvj420p, RGB, a clip flagged full range) are scaled to it."""
    from av.video.reformatter import ColorRange

    if frame.format.name != "yuv420p" or frame.color_range == ColorRange.JPEG:
        frame = frame.reformat(format="yuv420p", dst_color_range=ColorRange.MPEG)
    if frame.width < width or frame.height < height:
        raise VideoError(
            f"{path}: frame {index} is {frame.width}x{frame.height}, smaller than the first "
            f"frame's {width}x{height}"
        )
    out = np.empty((height * 3 // 2, width), dtype=np.uint8)
    targets = (out[:height], *out[height:].reshape(2, height // 2, width // 2))
    for plane, target in zip(frame.planes, targets, strict=True):
        rows = np.frombuffer(plane, dtype=np.uint8).reshape(plane.height, plane.line_size)
        target[:] = rows[: target.shape[0], : target.shape[1]]
    return out


class RawYuvSource:
    """Raw planar YUV 4:2:0 (I420) frames of a given size, as the classic test sequences ship.

    `clip_frames` is the number of frames in the file; `frame_count` the number `frames()`
    yields (None with `loop`).
    """

    def __init__(
        self, path: str | os.PathLike, width: int, height: int, fps: float, *, loop: bool = False
    ):
        self.path = Path(path)
        if width <= 0 or height <= 0 or width % 2 or height % 2:
            raise VideoError(
                f"{self.path}: expected an even positive frame size, got {width}x{height}"
            )
        size = check_regular_file(self.path, error=VideoError, what="YUV file")
        frame_bytes = width * height * 3 // 2
        if size == 0 or size % frame_bytes:
            raise VideoError(
                f"{self.path}: {size} bytes is not a whole number of {width}x{height} 4:2:0 "
                f"frames ({frame_bytes} bytes each)"
            )
        if not 0 < fps < float("inf"):  # --fps inf was a traceback deep in the bench
            raise VideoError(f"{self.path}: expected a positive frame rate, got {fps}")
        self.width, self.height, self.fps = width, height, float(fps)
        self.clip_frames = size // frame_bytes
        self.frame_count = None if loop else self.clip_frames
        self.loop = loop
        self.name = self.path.name

    def frames(self) -> Iterator[np.ndarray]:
        data = np.memmap(self.path, dtype=np.uint8, mode="r")
        shape = (self.clip_frames, self.height * 3 // 2, self.width)
        clip = data.reshape(shape)
        while True:
            for index in range(self.clip_frames):
                yield np.array(clip[index])
            if not self.loop:
                return


class PatternSource:
    """A synthetic scene with smooth motion and detail at several scales, deterministic from `seed`.

    A textured background pans slowly (a hand-held camera) while a textured ellipse of its own
    colour (a stand-in head) sways and nods over it, its texture sliding inside it (speech).
    Positions are sub-pixel (bilinear), so every frame differs from the last and motion is
    smooth; the head's edge is anti-aliased. Codecs get real work: edges, texture at several
    scales, global and local motion, chroma edges. Endless unless `frame_count` is given (the
    scene never repeats, so `loop` is not needed).
    """

    def __init__(
        self,
        width: int = 352,
        height: int = 288,
        fps: float = 25.0,
        *,
        seed: int = 0,
        frame_count: int | None = None,
    ):
        if width < 16 or height < 16 or width % 2 or height % 2:
            raise VideoError(
                f"pattern source: expected an even size of at least 16x16, got {width}x{height}"
            )
        if not fps > 0:
            raise VideoError(f"pattern source: expected a positive frame rate, got {fps}")
        if frame_count is not None and frame_count < 1:
            raise VideoError(f"pattern source: expected a positive frame_count, got {frame_count}")
        self.width, self.height, self.fps = width, height, float(fps)
        self.frame_count = frame_count
        self.name = "pattern"
        rng = np.random.default_rng(seed)
        self._margin = m = max(8, min(width, height) // 8)
        self._background = _texture(rng, height + 2 * m, width + 2 * m)
        self._background_u = _smooth(rng, height // 2 + m, width // 2 + m, 100.0, 150.0)
        self._background_v = _smooth(rng, height // 2 + m, width // 2 + m, 100.0, 150.0)
        self._head_h, self._head_w = int(0.72 * height) // 2 * 2, int(0.44 * width) // 2 * 2
        self._head = _texture(rng, self._head_h + 16, self._head_w) * 0.6 + 60.0
        yy, xx = np.mgrid[0 : self._head_h, 0 : self._head_w].astype(np.float32)
        ry, rx = self._head_h / 2, self._head_w / 2
        radius = np.sqrt(((yy + 0.5 - ry) / ry) ** 2 + ((xx + 0.5 - rx) / rx) ** 2)
        # about one pixel of soft edge, so sub-pixel positions show as sub-pixel edges
        self._head_alpha = np.clip((1.0 - radius) * min(rx, ry) + 0.5, 0.0, 1.0)

    def _frame(self, index: int) -> np.ndarray:
        import cv2

        h, w, m = self.height, self.width, self._margin
        hh, hw = self._head_h, self._head_w
        t = index / self.fps
        pan_x = (m - 1) * np.sin(0.21 * t)
        pan_y = (m - 1) * np.sin(0.13 * t + 1.0)
        background = cv2.getRectSubPix(
            self._background, (w, h), (m + pan_x + (w - 1) / 2, m + pan_y + (h - 1) / 2)
        )
        talk = 8 + 7 * np.sin(2.3 * t)  # the texture slides inside the head
        sprite = cv2.getRectSubPix(self._head, (hw, hh), ((hw - 1) / 2, talk + (hh - 1) / 2))
        x0 = (w - hw) / 2 + 0.08 * w * np.sin(0.9 * t)
        y0 = (h - hh) / 2 + 0.05 * h * np.sin(1.7 * t + 0.5)
        x0, y0 = min(max(x0, 0.0), w - hw), min(max(y0, 0.0), h - hh)
        move = np.float32([[1, 0, x0], [0, 1, y0]])
        alpha = cv2.warpAffine(self._head_alpha, move, (w, h), flags=cv2.INTER_LINEAR)
        head = cv2.warpAffine(sprite, move, (w, h), flags=cv2.INTER_LINEAR)
        frame = np.empty((h * 3 // 2, w), dtype=np.uint8)
        frame[:h] = np.clip(background + alpha * (head - background) + 0.5, 0, 255)
        chroma = frame[h:].reshape(2, h // 2, w // 2)
        alpha_c = cv2.resize(alpha, (w // 2, h // 2), interpolation=cv2.INTER_AREA)
        centre = (m / 2 + pan_x / 2 + (w // 2 - 1) / 2, m / 2 + pan_y / 2 + (h // 2 - 1) / 2)
        for plane, field, skin in ((0, self._background_u, 112.0), (1, self._background_v, 150.0)):
            moved = cv2.getRectSubPix(field, (w // 2, h // 2), centre)
            chroma[plane] = np.clip(moved + alpha_c * (skin - moved) + 0.5, 0, 255)
        return frame

    def frames(self) -> Iterator[np.ndarray]:
        index = 0
        while self.frame_count is None or index < self.frame_count:
            yield self._frame(index)
            index += 1


def _smooth(rng: np.random.Generator, h: int, w: int, low: float, high: float) -> np.ndarray:
    import cv2

    coarse = rng.random((max(2, h // 32), max(2, w // 32))).astype(np.float32)
    field = cv2.resize(coarse, (w, h), interpolation=cv2.INTER_CUBIC)
    return (low + (high - low) * np.clip(field, 0, 1)).astype(np.float32)


def _texture(rng: np.random.Generator, h: int, w: int) -> np.ndarray:
    """Noise summed over octaves (coarse shapes to fine detail), in [16, 235]."""
    import cv2

    total = np.zeros((h, w), dtype=np.float32)
    for octave, weight in ((64, 1.0), (16, 0.5), (4, 0.25), (1, 0.08)):
        coarse = rng.random((max(2, h // octave), max(2, w // octave))).astype(np.float32)
        total += weight * cv2.resize(coarse, (w, h), interpolation=cv2.INTER_CUBIC)
    total -= total.min()
    total /= max(float(total.max()), 1e-6)
    return (16 + 219 * total).astype(np.float32)
