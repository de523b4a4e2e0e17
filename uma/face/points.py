"""Feature-point files: clicked MPEG-4 points and the picture they were clicked on.

Units: pixels, x right, y down, (0, 0) the centre of the top-left pixel.

A points file is YAML or JSON: `{name: [x, y]}` at the top level, or under `points:` beside
optional keys naming the picture, as the files in `codecs/face/` do:

    video: shared:faces/video/akiyo.mp4   # or image: PATH (or skimage:NAME)
    frame: 0                              # which frame of the video (0-based)
    points: {"3.5": [190.0, 114.5], ...}

`shared:PATH` is PATH under the shared data folder (`uma.paths.shared_data_dir()`: the
`../shared/data` beside the clone, or `$UMA_SHARED_DATA`), so a file in the repository names
shared data wherever the clone sits; `skimage:NAME` is `skimage.data.NAME()`; any other value is
a path, relative to the points file's folder unless absolute.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from uma.errors import FaceError

__all__ = ["PointsFile", "load_points", "resolve_reference"]

SHARED_PREFIX = "shared:"
SKIMAGE_PREFIX = "skimage:"


@dataclass(frozen=True)
class PointsFile:
    """Points read from `path`, and the picture they belong to when the file says."""

    path: Path
    points: dict[str, tuple[float, float]] = field(default_factory=dict)
    video: Path | None = None
    frame: int | None = None
    image: str | None = None  # a resolved path, or "skimage:NAME"


def resolve_reference(value: str, base: Path) -> str:
    """A `video:`/`image:` value as a path string (or `skimage:NAME` kept as it is)."""
    from uma.paths import shared_data_dir

    if value.startswith(SKIMAGE_PREFIX):
        return value
    if value.startswith(SHARED_PREFIX):
        return str(shared_data_dir() / value[len(SHARED_PREFIX) :])
    path = Path(value).expanduser()
    return str(path if path.is_absolute() else base / path)


def load_points(
    path: str | Path, *, image: str | Path | None = None, face: int | None = None
) -> PointsFile:
    """Read a points file: YAML/JSON as above, or 68-point iBUG landmarks (`.pts`, dlib's
    `.xml`) mapped to MPEG-4 points by `uma.face.landmarks`. For an XML file, `image` says
    whose faces to take (and `face` which of them; default the largest)."""
    import yaml

    from uma.face.describe import read_points

    path = Path(path)
    if path.suffix.lower() in (".pts", ".xml"):
        from uma.face.landmarks import landmark_points

        points, picture = landmark_points(path, image=image, face=face)
        return PointsFile(
            path=path, points=points, image=str(picture) if picture is not None else None
        )
    points = read_points(path)
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    if not isinstance(data, dict) or not isinstance(data.get("points"), dict):
        return PointsFile(path=path, points=points)
    video = data.get("video")
    image = data.get("image")
    frame = data.get("frame")
    for key, value in (("video", video), ("image", image)):
        if value is not None and not (isinstance(value, str) and value.strip()):
            raise FaceError(f"{path}: {key}: expected a path (or shared:PATH), got {value!r}")
    if video is not None and image is not None:
        raise FaceError(f"{path}: give video: or image:, not both")
    if frame is not None and (isinstance(frame, bool) or not isinstance(frame, int) or frame < 0):
        raise FaceError(f"{path}: frame: expected a whole number >= 0, got {frame!r}")
    if frame is not None and video is None:
        raise FaceError(f"{path}: frame: {frame} given but no video: names the clip")
    base = path.parent
    return PointsFile(
        path=path,
        points=points,
        video=Path(resolve_reference(video, base)) if video is not None else None,
        frame=frame,
        image=resolve_reference(image, base) if image is not None else None,
    )
