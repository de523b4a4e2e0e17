"""The clips `uma bench codec` codes: streamed from the file (never held whole), bounded by
what the file holds, refused in one line when too small to score or too large to bench.

A clip is decoded once to count its frames and find the face box of each (the simulation's
`uma.face.region.FaceBoxes`), then again for every rung it is coded at: memory stays one
picture deep whatever the clip's length, and the work is the frames the file actually holds
(at most `--frames`), not the number asked for.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uma.errors import VideoError

__all__ = ["Clip", "open_clip", "work_pixels", "MIN_SIDE_PX", "MAX_PIXELS", "MIN_FRAMES"]

# SSIM's window is 7x7 and the face detector scans at least 16x16: a smaller picture cannot be
# scored. Above 4K UHD one frame's scoring at one rung holds gigabytes of float planes.
MIN_SIDE_PX = 16
MAX_PIXELS = 3840 * 2160
# A rate is measured after the first second; at a 5 frames/s rung 30 clip frames leave one.
MIN_FRAMES = 30


@dataclass(frozen=True)
class Clip:
    """A clip's name, picture size, frame count and face boxes; `frames()` decodes it anew."""

    name: str
    width: int
    height: int
    count: int
    boxes: tuple
    source_frames: Callable[[], Iterator[np.ndarray]]

    def frames(self) -> Iterator[np.ndarray]:
        return self.source_frames()


def _source(video: Path | None, count: int, pattern_size: tuple[int, int]):
    from uma.video import PatternSource, VideoFileSource

    if video is None:
        return PatternSource(*pattern_size, seed=0, frame_count=count), "pattern"
    source = VideoFileSource(video, max_frames=count)
    width, height = source.width, source.height
    if width < MIN_SIDE_PX or height < MIN_SIDE_PX:
        raise VideoError(
            f"{video}: a {width}x{height} picture is below the minimum {MIN_SIDE_PX}x"
            f"{MIN_SIDE_PX} the benchmark scores (SSIM's window is 7x7)"
        )
    if width * height > MAX_PIXELS:
        raise VideoError(
            f"{video}: a {width}x{height} picture ({width * height / 1e6:.1f} Mpixels) is above "
            f"the maximum 3840x2160 ({MAX_PIXELS / 1e6:.1f} Mpixels) the benchmark scores: "
            f"each frame is scored at every rung of every codec; scale the clip down first"
        )
    return source, video.stem.removesuffix("_qcif")


def open_clip(
    video: Path | None,
    count: int,
    *,
    pattern_size: tuple[int, int] = (352, 288),
    faces: bool = True,
) -> Clip:
    """The first `count` frames of `video` (fewer if it holds fewer), or of the built-in
    pattern at `pattern_size` when `video` is None; `faces=False` skips the face boxes.

    A file that is no video, a picture too small or too large to score, or a clip of fewer
    than `MIN_FRAMES` frames raises `VideoError` naming it.
    """
    from uma.face.region import FaceBoxes

    source, name = _source(video, count, pattern_size)
    boxes = FaceBoxes(source) if faces else None
    frames = source.frames() if boxes is None else boxes.wrap(source.frames())
    held = sum(1 for _ in frames)  # decodes (and detects) once, holding one picture
    if held < MIN_FRAMES:
        raise VideoError(
            f"{video}: {held} frames, expected at least {MIN_FRAMES} (the rate is measured "
            f"after the first second)"
        )
    return Clip(
        name=name,
        width=source.width,
        height=source.height,
        count=held,
        boxes=tuple(boxes.boxes) if boxes is not None else (),
        source_frames=source.frames,
    )


def work_pixels(videos: list[Path | None], frames: int, rungs: int) -> tuple[int, str]:
    """Pixels the benchmark will score (frames x picture x `rungs`), before any is decoded,
    and the largest clip's description; a clip that does not say how many frames it holds
    counts as `frames`. Refuses what `open_clip` would refuse, from the first frame alone."""
    total, largest, largest_pixels = 0, "", -1
    for video in videos:
        if video is None:
            width, height, count = 352, 288, frames
        else:
            source, _ = _source(video, frames, (352, 288))
            width, height = source.width, source.height
            count = source.clip_frames or _packets(video, frames)
            count = min(frames, count)
        total += count * width * height * rungs
        if width * height > largest_pixels:
            largest_pixels = width * height
            largest = f"{count} frames of {width}x{height}"
    return total, largest


def _packets(video: Path, limit: int) -> int:
    """The video packets in `video`, up to `limit`, read without decoding (a container such as
    Matroska does not say how many frames it holds)."""
    import av

    count = 0
    try:
        with av.open(str(video)) as container:
            for packet in container.demux(container.streams.video[0]):
                count += packet.size > 0
                if count >= limit:
                    break
    except av.FFmpegError as err:
        raise VideoError(f"{video}: cannot read its packets ({err})") from None
    return count
