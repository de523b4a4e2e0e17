"""One picture out of a video file: frame N of anything PyAV decodes, as a BGR image.

Units: frame indices count decoded pictures from 0 in presentation order (what `uma describe
VIDEO --frame N` and the clip points files in `codecs/face/` mean by a frame).

Decoding runs from the start up to the frame asked for: test clips are short (a few hundred
frames decode in well under a second), and seeking to a keyframe would depend on the file's
index and the decoder's delay, while counting decoded pictures gives the same frame for every
container.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uma.errors import VideoError

__all__ = ["read_frame"]


def read_frame(path: str | Path, index: int) -> np.ndarray:
    """Frame `index` (0-based) of the video at `path` as an (H, W, 3) uint8 BGR array.

    Raises `VideoError` naming the file for a missing file, a file that holds no decodable
    video, a negative index, or an index past the end (with the number of frames there are).
    """
    import av

    path = Path(path)
    if isinstance(index, bool) or not isinstance(index, int | np.integer) or index < 0:
        raise VideoError(f"{path}: frame index: expected a whole number >= 0, got {index!r}")
    if not path.is_file():
        raise VideoError(f"{path}: no such video file")
    count = 0
    try:
        with av.open(str(path)) as container:
            if not container.streams.video:
                raise VideoError(f"{path}: the file holds no video stream")
            for frame in container.decode(video=0):
                if count == index:
                    return np.ascontiguousarray(frame.to_ndarray(format="bgr24"))
                count += 1
    except av.FFmpegError as err:
        if count:
            raise VideoError(f"{path}: decoding failed after {count} frames ({err})") from None
        raise VideoError(f"{path}: not a video PyAV can decode ({err})") from None
    if count == 0:
        raise VideoError(f"{path}: the video stream holds no decodable frame")
    raise VideoError(
        f"{path}: frame {index} is past the end: the video has {count} frames (0-{count - 1})"
    )
