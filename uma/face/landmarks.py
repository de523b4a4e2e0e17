"""68-point iBUG landmarks (dlib's XML, the `.pts` text format) as MPEG-4 feature points.

Units: pixels, x right, y down, (0, 0) the centre of the top-left pixel.

Annotations people already have serve as clicks: the 68-point layout of iBUG's 300-W
(Sagonas et al., "300 Faces in-the-Wild Challenge", 2013; dlib's shape_predictor_68 marks the
same points) is mapped to the MPEG-4 points uma's model knows through `IBUG68_TO_MPEG4`.
The iBUG layout, 0-based as dlib names its parts `00`-`67`, with "left" and "right" the
subject's (iBUG numbers from the viewer's left, that is the subject's right side first):

    0-16   jaw line, from the subject's right ear (0) past the chin (8) to the left ear (16)
    17-21  right eyebrow, outer (17) to inner (21);   22-26 left eyebrow, inner (22) to outer (26)
    27-30  nose bridge, top (27) to tip (30);          31-35 nose base, right (31) to left (35)
    36-41  right eye: outer corner 36, upper lid 37 38, inner corner 39, lower lid 40 41
    42-47  left eye: inner corner 42, upper lid 43 44, outer corner 45, lower lid 46 47
    48-59  outer lip: right corner 48, upper lip 49-53 (top middle 51), left corner 54,
           lower lip 55-59 (bottom middle 57)
    60-67  inner lip: right corner 60, upper 61-63 (middle 62), left 64, lower 65-67 (middle 66)

An MPEG-4 point is the mean of the landmarks listed for it (a pupil: the six points round
its eye; an eyelid: the two points on that lid). Points the 68 do not mark are left out:
the chin's middle (2.10: iBUG has only the chin's bottom, 8), the inner lip corners (2.4,
2.5: uma's wireframe puts them on the outer corners' vertices, which 48 and 54 already give),
and the jaw corners (2.13, 2.14): iBUG's jaw line is the face's silhouette, while the model's
jaw corners sit inside it; fitted to the other points on the 43 faces of the shared dlib files,
the nearest jaw-line point (3 or 13) lies a median 11-13 % of the face's scale from them,
which would dominate the fit's error. The model's 9.15 sits on the nose bridge halfway from
the eyes to the tip, so it is the mean of bridge points 28 and 29.

Coordinates: dlib's XML is 0-based (pixel centres from 0). 300-W's `.pts` files are 1-based
(they were made for Matlab): `read_pts` subtracts 1 unless told `one_based=False`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uma.errors import FaceError

__all__ = [
    "IBUG68_TO_MPEG4",
    "N_LANDMARKS",
    "LandmarkFace",
    "read_pts",
    "parse_pts",
    "read_dlib_xml",
    "to_mpeg4",
    "landmark_points",
]

N_LANDMARKS = 68
MAX_LANDMARK_BYTES = 256 * 1024 * 1024  # dlib's 300-W training XML is about 40 MB

# MPEG-4 feature point -> the iBUG-68 landmarks (0-based) whose mean it is.
IBUG68_TO_MPEG4: dict[str, tuple[int, ...]] = {
    "3.5": (42, 43, 44, 45, 46, 47),  # left pupil: centre of the left eye's six points
    "3.6": (36, 37, 38, 39, 40, 41),  # right pupil
    "3.7": (45,),  # left eye, outer corner
    "3.8": (36,),  # right eye, outer corner
    "3.11": (42,),  # left eye, inner corner
    "3.12": (39,),  # right eye, inner corner
    "3.1": (43, 44),  # left upper eyelid
    "3.2": (37, 38),  # right upper eyelid
    "3.3": (46, 47),  # left lower eyelid
    "3.4": (40, 41),  # right lower eyelid
    "4.1": (22,),  # left eyebrow, inner
    "4.2": (21,),  # right eyebrow, inner
    "4.3": (24,),  # left eyebrow, middle
    "4.4": (19,),  # right eyebrow, middle
    "4.5": (26,),  # left eyebrow, outer
    "4.6": (17,),  # right eyebrow, outer
    "9.3": (30,),  # nose tip
    "9.1": (34,),  # left nostril
    "9.2": (32,),  # right nostril
    "9.15": (28, 29),  # nose bridge, halfway from the eyes to the tip
    "8.1": (51,),  # upper lip, top middle
    "8.2": (57,),  # lower lip, bottom middle
    "2.2": (62,),  # upper lip, inner middle
    "2.3": (66,),  # lower lip, inner middle
    "8.3": (54,),  # left lip corner
    "8.4": (48,),  # right lip corner
    "2.1": (8,),  # chin, bottom
}


@dataclass(frozen=True, eq=False)
class LandmarkFace:
    """One annotated face of a dlib XML file: its image (as the file names it), box, points."""

    image: str
    box: tuple[int, int, int, int]  # left, top, width, height in pixels
    landmarks: np.ndarray  # (68, 2); NaN where a part is absent


def to_mpeg4(landmarks: np.ndarray) -> dict[str, tuple[float, float]]:
    """MPEG-4 feature points from (68, 2) iBUG landmarks; a point whose landmarks are not all
    present (NaN) is left out."""
    landmarks = np.asarray(landmarks, dtype=np.float64)
    if landmarks.shape != (N_LANDMARKS, 2):
        raise FaceError(f"expected {N_LANDMARKS} landmarks (x, y), got shape {landmarks.shape}")
    points = {}
    for name, indices in IBUG68_TO_MPEG4.items():
        xy = landmarks[list(indices)]
        if np.all(np.isfinite(xy)):
            x, y = xy.mean(axis=0)
            points[name] = (float(x), float(y))
    return points


def parse_pts(text: str, *, where: str = "<pts>", one_based: bool = True) -> np.ndarray:
    """(N, 2) points from `.pts` text:

        version: 1
        n_points: 68
        {
        x y
        ...
        }

    Blank lines are allowed anywhere; anything else out of place is a `FaceError` naming
    `where` and the line.
    """
    lines = text.splitlines()
    numbered = [(k + 1, line.strip()) for k, line in enumerate(lines) if line.strip()]
    expect = iter(numbered)

    def take(what: str) -> tuple[int, str]:
        item = next(expect, None)
        if item is None:
            raise FaceError(f"{where}:{len(lines) + 1}: expected {what}, got the end of the file")
        return item

    count = _pts_header(take, where, len(numbered))
    number, line = take("'{'")
    if line != "{":
        raise FaceError(f"{where}:{number}: expected '{{', got {line!r}")
    points = np.array([_pts_point(take, where, k, count) for k in range(count)], dtype=float)
    number, line = take("'}'")
    if line != "}":
        raise FaceError(f"{where}:{number}: expected '}}' after {count} points, got {line!r}")
    extra = next(expect, None)
    if extra is not None:
        raise FaceError(f"{where}:{extra[0]}: expected the end of the file, got {extra[1]!r}")
    return points - 1.0 if one_based else points


def _pts_header(take, where: str, lines: int) -> int:
    """The point count of a `.pts` header ('version: 1', 'n_points: N'), read by `take`."""
    number, line = take("'version: 1'")
    key, _, value = line.partition(":")
    if key.strip() != "version" or value.strip() not in ("1", "1.0"):
        raise FaceError(f"{where}:{number}: expected 'version: 1', got {line!r}")
    number, line = take("'n_points: N'")
    key, _, value = line.partition(":")
    try:
        if key.strip() != "n_points":
            raise ValueError
        count = int(value.strip())
        if count <= 0:
            raise ValueError
    except ValueError:
        raise FaceError(f"{where}:{number}: expected 'n_points: N' (N > 0), got {line!r}") from None
    if count > lines:
        raise FaceError(
            f"{where}:{number}: n_points: {count} points announced, but the file has only "
            f"{lines} lines"
        )
    return count


def _pts_point(take, where: str, k: int, count: int) -> list[float]:
    """Point `k` (0-based) of `count` as [x, y], read by `take`."""
    number, line = take(f"point {k + 1} of {count} as 'x y'")
    fields = line.split()
    try:
        if len(fields) != 2:
            raise ValueError
        xy = [float(v) for v in fields]
        if not all(np.isfinite(xy)):
            raise ValueError
    except ValueError:
        raise FaceError(
            f"{where}:{number}: expected point {k + 1} of {count} as two numbers 'x y', "
            f"got {line!r}"
        ) from None
    return xy


def read_pts(path: str | Path, *, one_based: bool = True) -> np.ndarray:
    """(N, 2) points of a `.pts` file, 0-based (see `parse_pts`)."""
    from uma.paths import read_capped

    path = Path(path)
    data = read_capped(path, max_bytes=MAX_LANDMARK_BYTES, error=FaceError, what="landmark file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise FaceError(
            f"{path}: expected a .pts landmark file (text), got binary data (byte {err.start})"
        ) from None
    return parse_pts(text, where=str(path), one_based=one_based)


def read_dlib_xml(path: str | Path) -> list[LandmarkFace]:
    """Every annotated face of a dlib image-dataset XML file (`imglab`'s format):
    `<image file=...><box top= left= width= height=><part name="00" x= y=/>...`."""
    import xml.etree.ElementTree as ElementTree

    from uma.paths import read_capped

    path = Path(path)
    data = read_capped(path, max_bytes=MAX_LANDMARK_BYTES, error=FaceError, what="landmark file")
    try:
        root = ElementTree.fromstring(data)
    except ElementTree.ParseError as err:
        line = err.position[0] if err.position else "?"
        raise FaceError(f"{path}:{line}: not well-formed XML ({err})") from None
    except (LookupError, ValueError) as err:  # an encoding Python does not know, and the like
        raise FaceError(f"{path}: expected dlib landmark XML, got unreadable XML ({err})") from None
    faces = []
    for image in root.iter("image"):
        name = image.get("file")
        if not name:
            raise FaceError(f"{path}: an <image> without file=")
        for k, box in enumerate(image.iter("box")):
            where = f"{path}: {name} box {k}"
            try:
                left, top = int(box.get("left")), int(box.get("top"))
                width, height = int(box.get("width")), int(box.get("height"))
            except (TypeError, ValueError):
                raise FaceError(
                    f"{where}: expected whole-number left, top, width, height"
                ) from None
            landmarks = np.full((N_LANDMARKS, 2), np.nan)
            for part in box.iter("part"):
                label = part.get("name", "")
                try:
                    index = int(label)
                    x, y = float(part.get("x")), float(part.get("y"))
                except (TypeError, ValueError):
                    raise FaceError(
                        f"{where}: part {label!r}: expected name 00-67 and numbers x, y"
                    ) from None
                if not 0 <= index < N_LANDMARKS:
                    raise FaceError(f"{where}: part {label!r}: expected a name from 00 to 67")
                # dlib marks a part it could not place with coordinates near 2**31: absent.
                if abs(x) < 1e6 and abs(y) < 1e6:
                    landmarks[index] = (x, y)
            faces.append(
                LandmarkFace(image=name, box=(left, top, width, height), landmarks=landmarks)
            )
    return faces


def landmark_points(
    path: str | Path, *, image: str | Path | None = None, face: int | None = None
) -> tuple[dict[str, tuple[float, float]], Path | None, tuple[int, int, int, int] | None]:
    """MPEG-4 points from a landmark file, the image they belong to and the annotated face box
    (left, top, width, height; both None for `.pts`).

    `.pts`: the file's points. dlib XML: the faces of `image` (matched by path relative to
    the XML file, or else by file name); `face` picks one in file order, else the largest box.
    """
    path = Path(path)
    if path.suffix.lower() == ".pts":
        landmarks = read_pts(path)
        if landmarks.shape[0] != N_LANDMARKS:
            raise FaceError(
                f"{path}: expected the 68-point iBUG layout, got {landmarks.shape[0]} points"
            )
        return to_mpeg4(landmarks), None, None
    faces = read_dlib_xml(path)
    names = sorted({f.image for f in faces})
    if image is None:
        if len(names) == 1:
            image = names[0]
        else:
            raise FaceError(
                f"{path}: annotates {len(names)} images: name one (e.g. {names[0] if names else '?'})"
            )
    wanted = Path(image)
    chosen = [f for f in faces if _same_file(path.parent / f.image, wanted)]
    if not chosen:
        chosen = [f for f in faces if Path(f.image).name == wanted.name]
    if not chosen:
        raise FaceError(
            f"{path}: no face annotated for {wanted.name} (it annotates {len(names)} images)"
        )
    if face is not None:
        if not 0 <= face < len(chosen):
            raise FaceError(
                f"{path}: {wanted.name} has {len(chosen)} annotated faces (0-{len(chosen) - 1}), "
                f"not face {face}"
            )
        picked = chosen[face]
    else:
        picked = max(chosen, key=lambda f: f.box[2] * f.box[3])
    return to_mpeg4(picked.landmarks), path.parent / picked.image, picked.box


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.resolve() == b.resolve()
    except OSError:
        return False
