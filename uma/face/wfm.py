"""Read Candide-3 `.wfm` files (Ahlberg 2001) into a `FaceModel`.

The format: `# SECTION:` headers (VERTEX LIST, FACE LIST, ANIMATION UNITS LIST, SHAPE UNITS
LIST, then parameter sections), each followed by a count and that many entries; a unit is a
`# name` comment, a count, and `vertex dx dy dz` lines. Units are model units as in the file.
The file names no MPEG-4 feature points on its vertices; pass them as `feature_points`
(MPEG-4 name -> vertex number) to fit a Candide-3 model from clicked points.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uma.errors import FaceError
from uma.face.model import FaceModel

__all__ = ["read_wfm"]


class _Reader:
    def __init__(self, path: Path):
        self.path = path
        try:
            text = path.read_text(encoding="latin-1")
        except FileNotFoundError:
            raise FaceError(f"{path}: no such .wfm file") from None
        self.lines = [(n, line.strip()) for n, line in enumerate(text.splitlines(), 1)]
        self.pos = 0

    def fail(self, what: str) -> FaceError:
        n = self.lines[self.pos][0] if self.pos < len(self.lines) else len(self.lines)
        return FaceError(f"line {n} of {self.path}: {what}")

    def seek(self, header: str) -> None:
        for i in range(self.pos, len(self.lines)):
            if self.lines[i][1].upper().startswith(f"# {header}"):
                self.pos = i + 1
                return
        raise FaceError(f"{self.path}: no '# {header}' section")

    def next_data(self) -> tuple[int, str, str | None]:
        """The next non-blank, non-comment line, and the last comment before it."""
        comment = None
        while self.pos < len(self.lines):
            n, line = self.lines[self.pos]
            self.pos += 1
            if not line:
                continue
            if line.startswith("#"):
                comment = line.lstrip("#").strip()
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

    def units(self, header: str, n_vertices: int) -> tuple[tuple[str, ...], np.ndarray]:
        self.seek(header)
        count, _ = self.count(header.lower())
        names, arrays = [], []
        for _ in range(count):
            entries, name = self.count("unit entries")
            unit = np.zeros((n_vertices, 3))
            for _ in range(entries):
                index, dx, dy, dz = self.row(4, float, "'vertex dx dy dz'")
                if not index.is_integer() or not 0 <= index < n_vertices:
                    raise self.fail(f"vertex {index} outside 0-{n_vertices - 1}")
                unit[int(index)] = (dx, dy, dz)
            names.append(name or f"unit {len(names)}")
            arrays.append(unit)
        return tuple(names), np.array(arrays).reshape(-1, n_vertices, 3)


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
    action_names, action_units = reader.units("ANIMATION UNITS LIST", n_vertices)
    shape_names, shape_units = reader.units("SHAPE UNITS LIST", n_vertices)
    return FaceModel(
        name=path.stem,
        vertices=vertices,
        triangles=triangles,
        shape_units=shape_units,
        shape_unit_names=shape_names,
        action_units=action_units,
        action_unit_names=action_names,
        feature_points=dict(feature_points or {}),
    )
