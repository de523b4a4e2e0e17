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
from typing import Any

import numpy as np

from uma.errors import FaceError

__all__ = ["PointsFile", "load_points", "read_points", "resolve_reference", "MPEG4_POINTS"]

SHARED_PREFIX = "shared:"
SKIMAGE_PREFIX = "skimage:"

# ISO/IEC 14496-2 feature points: group -> how many points it has (2.1-2.14, 3.1-3.14, ...).
_GROUPS = {2: 14, 3: 14, 4: 6, 5: 4, 6: 4, 7: 1, 8: 10, 9: 15, 10: 10, 11: 6}
MPEG4_POINTS = frozenset(f"{g}.{k}" for g, n in _GROUPS.items() for k in range(1, n + 1))
_KNOWN = ", ".join(f"{g}.1-{g}.{n}" if n > 1 else f"{g}.1" for g, n in _GROUPS.items())
_PICTURE_KEYS = ("video", "image", "frame")


@dataclass(frozen=True)
class PointsFile:
    """Points read from `path`, and the picture they belong to when the file says. `frame`
    without `video` is a frame of the video the command line names."""

    path: Path
    points: dict[str, tuple[float, float]] = field(default_factory=dict)
    video: Path | None = None
    frame: int | None = None
    image: str | None = None  # a resolved path, or "skimage:NAME"
    box: tuple[int, int, int, int] | None = None  # the face box a landmark file annotates


def resolve_reference(value: str, base: Path) -> str:
    """A `video:`/`image:` value as a path string (or `skimage:NAME` kept as it is)."""
    from uma.paths import shared_data_dir

    if value.startswith(SKIMAGE_PREFIX):
        return value
    if value.startswith(SHARED_PREFIX):
        return str(shared_data_dir() / value[len(SHARED_PREFIX) :])
    path = Path(value).expanduser()
    return str(path if path.is_absolute() else base / path)


def _loader() -> type:
    """A safe loader that keeps mapping keys as written: `3.10:` stays "3.10", not 3.1."""
    import yaml

    class PointsLoader(yaml.SafeLoader):
        pass

    def mapping(loader: yaml.SafeLoader, node: yaml.MappingNode) -> dict:
        loader.flatten_mapping(node)
        out: dict[str, Any] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    "expected a point name as key, got a collection",
                    key_node.start_mark,
                )
            out[key_node.value] = loader.construct_object(value_node, deep=True)
        return out

    PointsLoader.add_constructor("tag:yaml.org,2002:map", mapping)
    return PointsLoader


def _key_lines(node: Any, path: Path, prefix: str) -> dict[str, int]:
    """Each key of a mapping node -> its 1-based line; a key given twice is refused (YAML
    would keep the last silently, and a pasted copy of a point would win over the one read)."""
    import yaml

    lines: dict[str, int] = {}
    if isinstance(node, yaml.MappingNode):
        for key_node, _ in node.value:
            name, line = key_node.value, key_node.start_mark.line + 1
            if name in lines:
                key = f"{prefix}[{name!r}]" if prefix else repr(name)
                raise FaceError(
                    f"{path}:{line} ({key}): duplicate key, already given on line {lines[name]}"
                )
            lines[name] = line
    return lines


def _parse(path: Path) -> tuple[dict[str, tuple[float, float]], dict[str, Any], dict[str, int]]:
    """(points, picture keys, line of each picture key) of a YAML/JSON points file."""
    import yaml

    from uma.face.yaml_text import read_yaml

    data, node = read_yaml(path, what="feature-point file (YAML or JSON)", loader=_loader())
    top = _key_lines(node, path, "")
    nested = isinstance(data, dict) and "points" in data
    if nested:
        # The node is None only for JSON that YAML cannot compose: then lines default to 1.
        points_node = next(
            (v for k, v in getattr(node, "value", ()) if getattr(k, "value", None) == "points"),
            None,
        )
        if not isinstance(data["points"], dict) or not data["points"]:
            raise FaceError(
                f"{path}:{top.get('points', 1)} (points): expected a mapping of feature point "
                f"names to [x, y], got {_short(data['points'])}"
            )
        extra = [k for k in data if k not in ("points", *_PICTURE_KEYS)]
        if extra:
            shown = extra[0] if extra[0].isidentifier() else _short(extra[0])
            raise FaceError(
                f"{path}:{top.get(extra[0], 1)} ({shown}): expected one of points, "
                f"{', '.join(_PICTURE_KEYS)}, got {_short(extra[0])}"
            )
        mapping, lines, prefix = data["points"], _key_lines(points_node, path, "points"), "points"
    elif isinstance(data, dict) and data:
        mapping, lines, prefix = data, top, ""
    else:
        line = node.start_mark.line + 1 if isinstance(node, yaml.Node) else 1
        raise FaceError(
            f"{path}:{line}: expected a mapping of feature point names to [x, y] "
            f"(or points: with video:/image:), got "
            f"{'an empty file' if data is None else _short(data)}"
        )
    points = {}
    for name, value in mapping.items():
        key = f"{prefix}[{name!r}]" if prefix else repr(name)
        where = f"{path}:{lines.get(name, 1)} ({key})"
        if name not in MPEG4_POINTS:
            raise FaceError(
                f"{where}: expected an MPEG-4 feature point ({_KNOWN}), got {_short(name)}"
            )
        ok = isinstance(value, list) and len(value) == 2
        ok = ok and all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        if not ok or not all(np.isfinite(value)):
            raise FaceError(f"{where}: expected [x, y] in finite pixels, got {_short(value)}")
        points[name] = (float(value[0]), float(value[1]))
    picture = {k: data[k] for k in _PICTURE_KEYS if nested and k in data}
    return points, picture, {k: top.get(k, 1) for k in _PICTURE_KEYS}


def _short(value: Any, limit: int = 40) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def read_points(path: str | Path) -> dict[str, tuple[float, float]]:
    """Feature points from YAML or JSON: `{name: [x, y]}`, at the top level or under `points:`;
    names are MPEG-4 feature points (`MPEG4_POINTS`)."""
    return _parse(Path(path))[0]


def load_points(
    path: str | Path, *, image: str | Path | None = None, face: int | None = None
) -> PointsFile:
    """Read a points file: YAML/JSON as above, or 68-point iBUG landmarks (`.pts`, dlib's
    `.xml`) mapped to MPEG-4 points by `uma.face.landmarks`. For an XML file, `image` says
    whose faces to take (and `face` which of them; default the largest)."""
    path = Path(path)
    if path.suffix.lower() in (".pts", ".xml"):
        from uma.face.landmarks import landmark_points

        points, picture, box = landmark_points(path, image=image, face=face)
        return PointsFile(
            path=path,
            points=points,
            image=str(picture) if picture is not None else None,
            box=box,
        )
    points, picture, lines = _parse(path)
    video, image, frame = (picture.get(k) for k in _PICTURE_KEYS)
    for key, value in (("video", video), ("image", image)):
        if value is not None and not (isinstance(value, str) and value.strip()):
            raise FaceError(
                f"{path}:{lines[key]} ({key}): expected a path (or shared:PATH), got {_short(value)}"
            )
    if video is not None and image is not None:
        raise FaceError(f"{path}:{lines['image']} (image): give video: or image:, not both")
    if frame is not None and (isinstance(frame, bool) or not isinstance(frame, int) or frame < 0):
        raise FaceError(
            f"{path}:{lines['frame']} (frame): expected a whole number >= 0, got {_short(frame)}"
        )
    if frame is not None and image is not None:
        raise FaceError(
            f"{path}:{lines['frame']} (frame): a frame is of a video, but the file names image:"
        )
    base = path.parent
    return PointsFile(
        path=path,
        points=points,
        video=Path(resolve_reference(video, base)) if video is not None else None,
        frame=frame,
        image=resolve_reference(image, base) if image is not None else None,
    )
