"""Read Candide-3 `.wfm` files (Ahlberg 2001) into a `FaceModel`.

The format: `# SECTION:` headers (VERTEX LIST, FACE LIST, ANIMATION UNITS LIST, SHAPE UNITS
LIST, then parameter sections), each followed by a count and that many entries; a unit is a
`# name` comment (for a FAP, a second comment names its FAP unit), a count, and
`vertex dx dy dz` lines. Units are model units as in the file.

The file does not label vertices with MPEG-4 feature points, but its FAP units say where each
FAP acts, and MPEG-4 ties every FAP to one feature point: the first vertex a FAP moves is taken as
that point (FAP 3 open_jaw -> 2.1 on the chin, FAP 53 stretch_l_cornerlip_o -> 8.3, ...). The
eye corners (3.7, 3.8, 3.11, 3.12) have no FAP; for Candide-3 itself they are the vertices
Ahlberg's drawing shows there. `feature_points` adds or overrides names.

Triangles are turned to wind counter-clockwise seen from the front (Candide-3 mostly winds them
the other way), so back-face culling works as for uma's own wireframe.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from uma.errors import FaceError
from uma.face.model import FaceModel

__all__ = ["read_wfm", "FAP_FEATURE_POINTS"]

# MPEG-4 FBA: the feature point each FAP moves (ISO/IEC 14496-2, table of FAPs). The eyeball
# FAPs (23-30) move the eyeball, not a vertex at the pupil, and are left out.
FAP_FEATURE_POINTS = {
    3: "2.1", 4: "2.2", 5: "2.3", 6: "2.4", 7: "2.5", 8: "2.6", 9: "2.7", 10: "2.8", 11: "2.9",
    12: "2.4", 13: "2.5", 14: "2.1", 15: "2.1", 16: "2.3", 17: "2.2", 18: "2.10",
    19: "3.1", 20: "3.2", 21: "3.3", 22: "3.4",
    31: "4.1", 32: "4.2", 33: "4.3", 34: "4.4", 35: "4.5", 36: "4.6", 37: "4.1", 38: "4.2",
    39: "5.1", 40: "5.2", 41: "5.3", 42: "5.4",
    51: "8.1", 52: "8.2", 53: "8.3", 54: "8.4", 55: "8.5", 56: "8.6", 57: "8.7", 58: "8.8",
    59: "8.3", 60: "8.4", 61: "9.1", 62: "9.2", 63: "9.3", 64: "9.3",
    65: "10.1", 66: "10.2", 67: "10.3", 68: "10.4",
}  # fmt: skip
# Candide-3 (113 vertices): eye corners, which no FAP moves.
CANDIDE3_EYE_CORNERS = {"3.7": 20, "3.8": 53, "3.11": 23, "3.12": 56}
_FAP_NAME = re.compile(r"FAP\s*(\d+)\b", re.IGNORECASE)


class _Reader:
    def __init__(self, path: Path):
        self.path = path
        try:
            text = path.read_text(encoding="latin-1")
        except FileNotFoundError:
            raise FaceError(f"{path}: no such .wfm file") from None
        self.lines = [(n, line.strip()) for n, line in enumerate(text.splitlines(), 1)]
        self.pos = 0

    def fail(self, what: str, *, back: bool = False) -> FaceError:
        """An error at the current line, or with `back` at the line just read."""
        pos = self.pos - 1 if back else self.pos
        n = self.lines[pos][0] if 0 <= pos < len(self.lines) else len(self.lines)
        return FaceError(f"line {n} of {self.path}: {what}")

    def seek(self, header: str) -> None:
        for i in range(self.pos, len(self.lines)):
            if self.lines[i][1].upper().startswith(f"# {header}"):
                self.pos = i + 1
                return
        raise FaceError(f"{self.path}: no '# {header}' section")

    def next_data(self) -> tuple[int, str, str | None]:
        """The next non-blank, non-comment line, and the first comment of the block before it
        (a unit's name; a FAP's unit, such as `# MNS`, may follow on the next comment line)."""
        comment = None
        while self.pos < len(self.lines):
            n, line = self.lines[self.pos]
            self.pos += 1
            if not line:
                comment = None  # a comment block ends at a blank line
                continue
            if line.startswith("#"):
                if comment is None:
                    comment = line.lstrip("#").strip() or None
                continue
            return n, line, comment
        raise self.fail("unexpected end of file")

    def count(self, what: str) -> tuple[int, str | None]:
        n, line, comment = self.next_data()
        try:
            value = int(line)
        except ValueError:
            raise FaceError(
                f"line {n} of {self.path}: expected the number of {what}, got {line!r}"
            ) from None
        if value < 0:
            raise FaceError(f"line {n} of {self.path}: expected a count >= 0, got {value}")
        return value, comment

    def row(self, width: int, kind, what: str) -> list:
        n, line, _ = self.next_data()
        fields = line.split()
        try:
            if len(fields) < width:
                raise ValueError
            return [kind(f) for f in fields[:width]]
        except ValueError:
            raise FaceError(f"line {n} of {self.path}: expected {what}, got {line!r}") from None

    def units(
        self, header: str, n_vertices: int
    ) -> tuple[tuple[str, ...], np.ndarray, list[int | None]]:
        """Names, (U, N, 3) displacements, and the first vertex each unit moves."""
        self.seek(header)
        count, _ = self.count(header.lower())
        names, arrays, firsts = [], [], []
        for _ in range(count):
            entries, name = self.count("unit entries")
            unit = np.zeros((n_vertices, 3))
            first = None
            for _ in range(entries):
                index, dx, dy, dz = self.row(4, float, "'vertex dx dy dz'")
                if not index.is_integer() or not 0 <= index < n_vertices:
                    raise self.fail(f"vertex {index:g} outside 0-{n_vertices - 1}", back=True)
                unit[int(index)] = (dx, dy, dz)
                first = int(index) if first is None else first
            names.append(name or f"unit {len(names)}")
            arrays.append(unit)
            firsts.append(first)
        return tuple(names), np.array(arrays).reshape(-1, n_vertices, 3), firsts


def read_wfm(path: str | Path, *, feature_points: dict[str, int] | None = None) -> FaceModel:
    """Parse a Candide-3 `.wfm`; a malformed section raises `FaceError` naming file and line."""
    path = Path(path)
    reader = _Reader(path)
    reader.seek("VERTEX LIST")
    n_vertices, _ = reader.count("vertices")
    vertices = np.array([reader.row(3, float, "'x y z'") for _ in range(n_vertices)]).reshape(-1, 3)
    reader.seek("FACE LIST")
    n_faces, _ = reader.count("faces")
    triangles = np.array(
        [reader.row(3, int, "three vertex numbers") for _ in range(n_faces)]
    ).reshape(-1, 3)
    triangles = _counter_clockwise(vertices, triangles)
    action_names, action_units, firsts = reader.units("ANIMATION UNITS LIST", n_vertices)
    shape_names, shape_units, _ = reader.units("SHAPE UNITS LIST", n_vertices)
    points = _fap_feature_points(action_names, firsts)
    if reader.lines and reader.lines[0][1].lower().startswith("# candide-3") and n_vertices == 113:
        points |= CANDIDE3_EYE_CORNERS
    points |= dict(feature_points or {})
    try:
        return FaceModel(
            name=path.stem,
            vertices=vertices,
            triangles=triangles,
            shape_units=shape_units,
            shape_unit_names=shape_names,
            action_units=action_units,
            action_unit_names=action_names,
            feature_points=points,
        )
    except FaceError as err:
        raise FaceError(f"{path}: {err}") from None


def _counter_clockwise(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Triangles wound counter-clockwise seen from the front, as uma's culling expects.

    Candide-3 lists most of its triangles clockwise and a few the other way; a face mask faces
    the camera everywhere, so each triangle is turned to face +z in the frontal view.
    """
    if triangles.size == 0 or triangles.min() < 0 or triangles.max() >= len(vertices):
        return triangles  # FaceModel reports the bad vertex number
    a, b, c = (vertices[triangles[:, k], :2] for k in range(3))
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    out = triangles.copy()
    out[cross < 0] = out[cross < 0][:, [0, 2, 1]]
    return out


def _fap_feature_points(names: tuple[str, ...], firsts: list[int | None]) -> dict[str, int]:
    """MPEG-4 feature points from FAP units: the first vertex each FAP moves (first FAP wins)."""
    points: dict[str, int] = {}
    for name, first in zip(names, firsts, strict=True):
        match = _FAP_NAME.match(name)
        if match is None or first is None:
            continue
        point = FAP_FEATURE_POINTS.get(int(match.group(1)))
        if point is not None:
            points.setdefault(point, first)
    return points
