"""`uma bench mbc`'s clips: the talking head, akiyo and carphone, foreman from raw YUV, a file.

Units: pixels, frames per second. Pictures are YUV 4:2:0 (H * 3 // 2, W) uint8.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "ClipSpec",
    "FOREMAN",
    "check_clip",
    "check_first_frame",
    "default_clips",
    "file_clip",
    "foreman_clip",
    "talking_head_clip",
    "yuv_clip",
]

# The raw QCIF foreman excerpt in the shared data folder (48 frames, 25 frames/s).
FOREMAN = Path("faces/video/foreman_part_qcif.yuv")
FOREMAN_SIZE = (176, 144)


def yuv_clip(path: Path, size: tuple[int, int], fps: float, description, frames: int, name=None):
    """`frames` frames (at most the file's) of raw YUV 4:2:0 `path` of `size` (W, H)."""
    from uma.video.sources import RawYuvSource

    source = RawYuvSource(path, *size, fps)
    pictures = []
    for picture in source.frames():
        if len(pictures) == frames:
            break
        pictures.append(picture)
    return ClipSpec(name or path.stem, pictures, fps, description, None, str(path))


def foreman_clip(frames: int):
    """Foreman from raw YUV with a description fitted to the points shipped in
    `codecs/face/foreman.yaml` (its frame 0; `uma describe` refuses it: the detector finds no
    face cut by the picture's top edge, `describe` itself needs none); None when the shared
    data folder has no foreman."""
    import cv2

    from uma.face.describe import describe
    from uma.face.points import read_points
    from uma.mbc.profile import with_sender_ring
    from uma.paths import codecs_dir, shared_data_dir
    from uma.video.sources import RawYuvSource

    path = shared_data_dir() / FOREMAN
    if not path.is_file():
        return None
    first = next(RawYuvSource(path, *FOREMAN_SIZE, 25.0).frames())
    points = read_points(codecs_dir() / "face" / "foreman.yaml")
    description = describe(cv2.cvtColor(first, cv2.COLOR_YUV2BGR_I420), points)
    if not description:
        return None
    clip = yuv_clip(path, FOREMAN_SIZE, 25.0, description, frames, name="foreman")
    return replace(clip, description=with_sender_ring(description, clip.frames))


@dataclass(frozen=True, eq=False)
class ClipSpec:
    """A clip to code: YUV 4:2:0 frames, its rate, the description, ground truth if any."""

    name: str
    frames: list[np.ndarray]
    fps: float
    description: Any  # ContentDescription
    truth: Callable[[int], np.ndarray] | None = None
    where: str = ""


def check_clip(clip: ClipSpec, face: str | Path) -> None:
    """Refuse, in one line, a clip the bench cannot score: fewer than 2 frames (frame 0 is the
    reference, the others are scored: one frame gave every PSNR as 0.0), or a description
    `face` whose texture lies past the clip's pictures (made from a larger clip: its face was
    drawn off the picture). One pixel of slack: an odd-sized clip is cropped to even."""
    from uma.errors import FaceError, VideoError

    where = clip.where or clip.name
    if len(clip.frames) < 2:
        raise VideoError(
            f"{where}: holds {len(clip.frames)} frame(s): expected at least 2 (the first is the "
            "reference, the others are scored)"
        )
    height, width = clip.frames[0].shape[0] * 2 // 3, clip.frames[0].shape[1]
    x0, y0 = (int(round(v)) for v in clip.description.origin_px)
    right, bottom = x0 + clip.description.texture.shape[1], y0 + clip.description.texture.shape[0]
    if right > width + 1 or bottom > height + 1:
        raise FaceError(
            f"{face}: its texture reaches to x {right}, y {bottom}, past {where}'s "
            f"{width}x{height} pictures: expected a description made from a frame of this clip "
            "(uma describe)"
        )


def check_first_frame(clip: ClipSpec) -> None:
    """Refuse, in one line, a clip whose frame 0 holds nothing to fit (flat or saturated: a
    black or blank opening): the bench renders the scene from frame 0 at the pose tracked there,
    and on 10 black frames it drew the face over grey and scored frames with no face in them
    (face PSNR 49 dB). A frame 0 that shows a picture but where the tracker finds no face runs
    on, from the description's own picture (`uma.bench.mbc`'s `reference` says so)."""
    from uma.errors import VideoError
    from uma.fit.fit import check_image

    first = clip.frames[0]
    failure = check_image(first[: first.shape[0] * 2 // 3])  # a Failure (false) or None
    if failure is None:
        return
    raise VideoError(
        f"{clip.where or clip.name}: frame 0: {failure.reason}: expected a clip that opens on the"
        " face the description shows (the bench renders the scene from its first frame): cut it"
        " to start where the face is"
    )


def talking_head_clip(frames: int, *, seed: int = 0, start: int = 0) -> ClipSpec:
    import cv2

    from uma.face.talking_head import TalkingHeadSource

    source = TalkingHeadSource(352, 288, seed=seed)
    noise = np.random.default_rng(seed)
    yuv = [
        cv2.cvtColor(source.render_bgr(i, rng=noise), cv2.COLOR_BGR2YUV_I420)
        for i in range(start, start + frames)
    ]
    truth = source.params_at if not start else (lambda i: source.params_at(i + start))
    return ClipSpec("talking-head", yuv, source.fps, source.description, truth, "talking head")


def file_clip(
    video: Path, description, frames: int, *, name: str | None = None, start: int = 0
) -> ClipSpec:
    """`frames` frames of `video` from frame `start`."""
    from uma.video import VideoFileSource

    source = VideoFileSource(video, max_frames=start + frames)
    pictures = list(source.frames())[start:]
    return ClipSpec(name or video.stem, pictures, source.fps, description, None, str(video))


def default_clips(frames: int, *, seed: int = 0, start: int = 0) -> list[ClipSpec]:
    """The talking head, then akiyo and carphone with the shipped clicked points and foreman
    from raw YUV (its 48 frames; skipped when ../shared/data is absent, or from `start` on),
    `frames` frames from frame `start` (tuning uses 150)."""
    from uma.face.clip import load_points
    from uma.mbc.profile import describe_clip_with_ring
    from uma.paths import codecs_dir

    clips = [talking_head_clip(frames, seed=seed, start=start)]
    for name in ("akiyo", "carphone"):
        points_file = codecs_dir() / "face" / f"{name}.yaml"
        points = load_points(points_file)
        video = Path(points.video) if points.video is not None else None
        if video is None or not video.is_file():
            continue
        description = describe_clip_with_ring(points, seed=seed)
        clips.append(file_clip(video, description, frames, name=name, start=start))
    if not start:
        foreman = foreman_clip(frames)
        if foreman is not None:
            clips.append(foreman)
    return clips
