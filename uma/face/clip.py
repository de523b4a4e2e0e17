"""Content descriptions of real clips: the picture a points file names, described.

Units: pixels; frame indices are 0-based decoded pictures.

`describe_clip("codecs/face/akiyo.yaml")` is what `uma describe --points codecs/face/akiyo.yaml`
does without the command line: decode the frame the file names, fit the model to its points,
and return the content description (texture cut from that frame); for a video `uma describe`
adds the sender's head ring (`uma.mbc.profile.describe_clip_with_ring`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uma.errors import FaceError, VideoError
from uma.face.describe import ContentDescription, describe
from uma.face.image_bytes import decode_image, what_the_bytes_look_like
from uma.face.model import FaceModel
from uma.face.points import SKIMAGE_PREFIX, PointsFile, load_points

__all__ = ["SHIPPED_CLIPS", "shipped_points", "read_picture", "picture_of", "describe_clip"]

# Clip name (as `uma bench mbc` names clips) -> its hand-clicked points in codecs/face/.
SHIPPED_CLIPS = {"akiyo": "akiyo.yaml", "carphone": "carphone.yaml", "astronaut": "astronaut.yaml"}


def shipped_points(name: str) -> Path:
    """The points file shipped for clip `name` (`akiyo`, `carphone`, `astronaut`)."""
    from uma.paths import codecs_dir

    if name not in SHIPPED_CLIPS:
        raise FaceError(
            f"no shipped points for {name!r}: expected one of {', '.join(SHIPPED_CLIPS)}"
        )
    return codecs_dir() / "face" / SHIPPED_CLIPS[name]


def read_picture(
    path: str | Path, *, frame: int | None = None, video_frame: int | None = None
) -> np.ndarray:
    """A BGR picture: the still image at `path` (anything OpenCV reads), or frame `frame` of
    the video at `path` (anything PyAV decodes). `video_frame` is the frame to take when `path`
    is a video and `frame` is None (a points file's `frame:`); a still ignores it.

    A still is tried first; what OpenCV cannot read goes to PyAV (a file named like a video,
    `.mp4` and the like, goes to PyAV at once, so a long clip is not read into memory). `frame`
    given for a still, or missing for a video, is a `FaceError`/`VideoError` naming the file.
    """
    import cv2

    from uma.video.frame import read_frame

    if str(path).startswith(SKIMAGE_PREFIX):
        return _skimage(str(path), frame)
    from uma.paths import check_regular_file

    path = Path(path)
    if not path.is_dir():  # a folder keeps its own message below
        # a FIFO or device would block the read, a symlink loop would raise deep in pathlib
        check_regular_file(path, error=FaceError, what="image or video file")
    if path.suffix.lower() in VIDEO_SUFFIXES and path.is_file():
        frame = frame if frame is not None else video_frame
        if frame is None:
            raise FaceError(
                f"{path}: is a video: say which frame (--frame N, or frame: in the points)"
            )
        return _video_frame(path, frame)
    try:
        data = np.frombuffer(path.read_bytes(), dtype=np.uint8)
    except FileNotFoundError:
        raise FaceError(f"{path}: no such image or video file") from None
    except IsADirectoryError:
        raise FaceError(f"{path}: is a folder, not an image or video file") from None
    except OSError as err:
        raise FaceError(f"{path}: cannot read ({err.strerror})") from None
    image = decode_image(data, cv2.IMREAD_COLOR) if data.size else None
    if image is not None:
        if frame is not None:
            raise FaceError(f"{path}: a still image has no frame {frame}: --frame is for videos")
        return image
    looks_like = what_the_bytes_look_like(data.tobytes()[:512])
    if looks_like.endswith(" image"):
        # PyAV opens a damaged JPEG or PNG as a one-frame "video"; it is a picture that failed.
        raise FaceError(
            f"{path}: expected an image OpenCV can decode, got {looks_like} that is truncated or "
            "damaged"
        )
    frame = frame if frame is not None else video_frame
    if frame is None:
        try:
            read_frame(path, 0)
        except VideoError:
            raise FaceError(
                f"{path}: neither an image OpenCV reads nor a video PyAV decodes"
            ) from None
        raise FaceError(f"{path}: is a video: say which frame (--frame N, or frame: in the points)")
    return _video_frame(path, frame)


# Suffixes taken for videos without trying OpenCV first.
VIDEO_SUFFIXES = frozenset(
    [
        ".mp4",
        ".m4v",
        ".mov",
        ".avi",
        ".mkv",
        ".webm",
        ".mpg",
        ".mpeg",
        ".ts",
        ".flv",
        ".3gp",
        ".wmv",
        ".y4m",
        ".h264",
        ".264",
    ]
)


def _video_frame(path: Path, frame: int) -> np.ndarray:
    from uma.video.frame import read_frame

    try:
        return read_frame(path, frame)
    except VideoError as err:
        if "not a video" in str(err) or "no video stream" in str(err):
            raise FaceError(
                f"{path}: neither an image OpenCV reads nor a video PyAV decodes"
            ) from None
        raise


def _skimage(reference: str, frame: int | None) -> np.ndarray:
    import cv2
    import skimage.data

    name = reference[len(SKIMAGE_PREFIX) :]
    loader = getattr(skimage.data, name, None)
    if frame is not None:
        raise FaceError(f"{reference}: a still image has no frame {frame}")
    if loader is None or not callable(loader):
        raise FaceError(f"{reference}: scikit-image ships no picture {name!r}")
    image = np.asarray(loader())
    if image.ndim == 2:
        return cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
    return cv2.cvtColor(image[..., :3], cv2.COLOR_RGB2BGR)


def picture_of(points: PointsFile, *, frame: int | None = None) -> np.ndarray:
    """The picture `points` names (its `video:` at `frame:` or its `image:`); `frame`
    overrides the file's frame."""
    if points.video is not None:
        return read_picture(points.video, frame=frame if frame is not None else points.frame)
    if points.image is not None:
        return read_picture(points.image, frame=frame)
    if points.frame is not None:
        raise FaceError(
            f"{points.path}: frame: {points.frame} given but no video: names the clip "
            "(name it in the file, or give VIDEO)"
        )
    raise FaceError(f"{points.path}: names no picture (video: or image:)")


def describe_clip(
    points_file: str | Path | PointsFile,
    *,
    model: FaceModel | None = None,
    crop: bool = True,
    ridge_px: float | None = None,
) -> ContentDescription:
    """The content description of the clip (or image) a points file names, as `uma describe`
    writes it: e.g. `describe_clip(shipped_points("akiyo"))`. With `crop=False` the texture is
    the whole frame; `ridge_px` as in `describe`.

    Raises `FaceError` (or `VideoError`) naming the file when the picture cannot be read, no
    face the detector finds holds the points, or the points do not fit the model.
    """
    import cv2

    from uma.face.detect import Box, locate_points

    points = points_file if isinstance(points_file, PointsFile) else load_points(points_file)
    picture = picture_of(points)
    # As `uma describe`: points that lie on no face the detector finds are not this picture's.
    annotated = Box(*points.box) if points.box is not None else None
    placed = locate_points(
        cv2.cvtColor(picture, cv2.COLOR_BGR2GRAY), points.points, annotated=annotated
    )
    if not placed:
        raise FaceError(f"{points.path}: {placed.reason}")
    result = describe(picture, points.points, model=model, crop=crop, ridge_px=ridge_px)
    if not result:
        raise FaceError(f"{points.path}: {result.reason}")
    return result
