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

__all__ = ["VideoFileSource", "RawYuvSource", "PatternSource"]


class VideoFileSource:
    """Frames decoded from a file by PyAV; odd sizes are cropped to even."""

    def __init__(
        self, path: str | os.PathLike, *, loop: bool = False, max_frames: int | None = None
    ):
        import av

        self.path = Path(path)
        self.loop = loop
        self.max_frames = max_frames
        if not self.path.is_file():
            raise VideoError(f"{self.path}: no such video file")
        try:
            with av.open(str(self.path)) as container:
                if not container.streams.video:
                    raise VideoError(f"{self.path}: no video stream")
                stream = container.streams.video[0]
                rate = stream.average_rate or stream.guessed_rate
                self.fps = float(rate) if rate else 25.0
                first = next(container.decode(stream), None)
                self.frame_count = stream.frames or None
        except av.FFmpegError as err:
            raise VideoError(f"{self.path}: cannot decode as video ({err})") from None
        if first is None:
            raise VideoError(f"{self.path}: the video stream holds no decodable frame")
        self.width = first.width - first.width % 2
        self.height = first.height - first.height % 2
        self.name = self.path.name

    def _once(self) -> Iterator[np.ndarray]:
        import av

        try:
            with av.open(str(self.path)) as container:
                for frame in container.decode(video=0):
                    array = frame.to_ndarray(format="yuv420p")
                    if frame.width != self.width or frame.height != self.height:
                        array = _crop_yuv420(
                            array, frame.width, frame.height, self.width, self.height
                        )
                    yield array
        except av.FFmpegError as err:
            raise VideoError(f"{self.path}: decoding failed ({err})") from None

    def frames(self) -> Iterator[np.ndarray]:
        produced = 0
        while True:
            empty = True
            for array in self._once():
                empty = False
                yield array
                produced += 1
                if self.max_frames is not None and produced >= self.max_frames:
                    return
            if not self.loop or empty:
                return


def _crop_yuv420(array: np.ndarray, width: int, height: int, new_w: int, new_h: int) -> np.ndarray:
    cw, ch = (width + 1) // 2, (height + 1) // 2
    flat = array.reshape(-1)
    y = flat[: width * height].reshape(height, width)[:new_h, :new_w]
    u = flat[width * height : width * height + cw * ch].reshape(ch, cw)[: new_h // 2, : new_w // 2]
    v = flat[width * height + cw * ch :].reshape(ch, cw)[: new_h // 2, : new_w // 2]
    return np.concatenate([y.reshape(-1), u.reshape(-1), v.reshape(-1)]).reshape(-1, new_w)


class RawYuvSource:
    """Raw planar YUV 4:2:0 (I420) frames of a given size, as the classic test sequences ship."""

    def __init__(
        self, path: str | os.PathLike, width: int, height: int, fps: float, *, loop: bool = False
    ):
        self.path = Path(path)
        if width <= 0 or height <= 0 or width % 2 or height % 2:
            raise VideoError(
                f"{self.path}: expected an even positive frame size, got {width}x{height}"
            )
        if not self.path.is_file():
            raise VideoError(f"{self.path}: no such YUV file")
        frame_bytes = width * height * 3 // 2
        size = self.path.stat().st_size
        if size == 0 or size % frame_bytes:
            raise VideoError(
                f"{self.path}: {size} bytes is not a whole number of {width}x{height} 4:2:0 "
                f"frames ({frame_bytes} bytes each)"
            )
        self.width, self.height, self.fps = width, height, float(fps)
        self.frame_count = size // frame_bytes
        self.loop = loop
        self.name = self.path.name

    def frames(self) -> Iterator[np.ndarray]:
        data = np.memmap(self.path, dtype=np.uint8, mode="r")
        shape = (self.frame_count, self.height * 3 // 2, self.width)
        clip = data.reshape(shape)
        while True:
            for index in range(self.frame_count):
                yield np.array(clip[index])
            if not self.loop:
                return


class PatternSource:
    """A synthetic scene with motion and detail at several scales, deterministic from `seed`.

    A textured background pans slowly while a textured ellipse (a stand-in head) sways and
    nods over it; chroma varies smoothly. Codecs get real work: edges, texture and motion.
    """

    def __init__(self, width: int = 352, height: int = 288, fps: float = 25.0, *, seed: int = 0):
        if width <= 0 or height <= 0 or width % 2 or height % 2:
            raise VideoError(
                f"pattern source: expected an even positive size, got {width}x{height}"
            )
        self.width, self.height, self.fps = width, height, float(fps)
        self.frame_count = None
        self.name = "pattern"
        rng = np.random.default_rng(seed)
        self._margin = max(8, min(width, height) // 8)
        m = self._margin
        self._background = _texture(rng, height + 2 * m, width + 2 * m).astype(np.uint8)
        # The head: an ellipse of its own texture, drawn from a precomputed sprite and mask.
        self._head_h, self._head_w = int(0.72 * height) // 2 * 2, int(0.44 * width) // 2 * 2
        yy, xx = np.mgrid[0 : self._head_h, 0 : self._head_w]
        ry, rx = (self._head_h - 1) / 2, (self._head_w - 1) / 2
        self._head_mask = ((yy - ry) / ry) ** 2 + ((xx - rx) / rx) ** 2 <= 1.0
        self._head = (_texture(rng, self._head_h + 8, self._head_w) * 0.6 + 60).astype(np.uint8)
        self._chroma_u = _smooth(rng, height // 2, width // 2, 110, 146)
        self._chroma_v = _smooth(rng, height // 2, width // 2, 110, 146)

    def frames(self) -> Iterator[np.ndarray]:
        h, w, m = self.height, self.width, self._margin
        hh, hw = self._head_h, self._head_w
        index = 0
        while True:
            t = index / self.fps
            ox = int(round(m + (m - 1) * np.sin(0.21 * t)))
            oy = int(round(m + (m - 1) * np.sin(0.13 * t + 1.0)))
            frame = np.empty((h * 3 // 2, w), dtype=np.uint8)
            luma = frame[:h]
            luma[:] = self._background[oy : oy + h, ox : ox + w]
            x0 = int(round((w - hw) / 2 + 0.08 * w * np.sin(0.9 * t)))
            y0 = int(round((h - hh) / 2 + 0.05 * h * np.sin(1.7 * t + 0.5)))
            x0, y0 = min(max(x0, 0), w - hw), min(max(y0, 0), h - hh)
            talk = int(round(4 + 4 * np.sin(2.3 * t)))  # texture moves inside the head
            region = luma[y0 : y0 + hh, x0 : x0 + hw]
            np.copyto(region, self._head[talk : talk + hh], where=self._head_mask)
            chroma = frame[h:].reshape(2, h // 2, w // 2)
            chroma[0] = self._chroma_u
            chroma[1] = self._chroma_v
            yield frame
            index += 1


def _smooth(rng: np.random.Generator, h: int, w: int, low: float, high: float) -> np.ndarray:
    import cv2

    coarse = rng.random((max(2, h // 32), max(2, w // 32))).astype(np.float32)
    field = cv2.resize(coarse, (w, h), interpolation=cv2.INTER_CUBIC)
    return (low + (high - low) * np.clip(field, 0, 1)).astype(np.uint8)


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
