"""The wireframe face model: vertices, triangles, shape and action units, MPEG-4 feature points.

Units: model coordinates, unitless, x to the viewer's right, y up, z toward the camera; the
face is about 2 units tall (chin at y = -0.82, hairline near y = 1.1; a unit is ~10 cm). Triangles wind
counter-clockwise seen from the front, for back-face culling.

Files: uma's own YAML (`codecs/face/uma-face.yaml`, `read_model_yaml`) and Candide-3 `.wfm`
(`uma.face.wfm.read_wfm`); `uma.face.load.load_model` reads either.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from uma.errors import FaceError

__all__ = ["FaceModel", "read_model_yaml", "save_model", "default_model_path"]


@dataclass(frozen=True, eq=False)
class FaceModel:
    """A wireframe with its deformation units; arrays are read-only after construction."""

    name: str
    vertices: np.ndarray  # (N, 3)
    triangles: np.ndarray  # (T, 3) int32
    shape_units: np.ndarray  # (S, N, 3)
    shape_unit_names: tuple[str, ...]
    action_units: np.ndarray  # (A, N, 3)
    action_unit_names: tuple[str, ...]
    feature_points: Mapping[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        vertices = np.asarray(self.vertices, dtype=np.float64)
        triangles = np.asarray(self.triangles, dtype=np.int32)
        n = vertices.shape[0]
        shape_units = np.asarray(self.shape_units, dtype=np.float64).reshape(-1, n, 3)
        action_units = np.asarray(self.action_units, dtype=np.float64).reshape(-1, n, 3)
        if vertices.ndim != 2 or vertices.shape[1] != 3 or n < 3:
            raise FaceError(f"{self.name}: vertices must be an (N, 3) array, got {vertices.shape}")
        if triangles.ndim != 2 or triangles.shape[1] != 3 or triangles.size == 0:
            raise FaceError(f"{self.name}: triangles must be a (T, 3) array, got {triangles.shape}")
        if triangles.min() < 0 or triangles.max() >= n:
            raise FaceError(f"{self.name}: a triangle names a vertex outside 0-{n - 1}")
        if len(self.shape_unit_names) != shape_units.shape[0]:
            raise FaceError(
                f"{self.name}: {shape_units.shape[0]} shape units but {len(self.shape_unit_names)} names"
            )
        if len(self.action_unit_names) != action_units.shape[0]:
            raise FaceError(
                f"{self.name}: {action_units.shape[0]} action units but {len(self.action_unit_names)} names"
            )
        for point, index in self.feature_points.items():
            if not 0 <= index < n:
                raise FaceError(
                    f"{self.name}: feature point {point} names vertex {index}, outside 0-{n - 1}"
                )
        for array in (vertices, triangles, shape_units, action_units):
            array.setflags(write=False)
        object.__setattr__(self, "vertices", vertices)
        object.__setattr__(self, "triangles", triangles)
        object.__setattr__(self, "shape_units", shape_units)
        object.__setattr__(self, "action_units", action_units)
        object.__setattr__(self, "shape_unit_names", tuple(self.shape_unit_names))
        object.__setattr__(self, "action_unit_names", tuple(self.action_unit_names))
        object.__setattr__(self, "feature_points", dict(self.feature_points))

    @property
    def n_vertices(self) -> int:
        return self.vertices.shape[0]

    @property
    def n_actions(self) -> int:
        return self.action_units.shape[0]

    @property
    def n_shapes(self) -> int:
        return self.shape_units.shape[0]

    def personalised(self, shape: np.ndarray) -> FaceModel:
        """The model with shape coefficients baked into its vertices (S(P) of the pipeline)."""
        shape = np.asarray(shape, dtype=np.float64)
        if shape.shape != (self.n_shapes,):
            raise FaceError(
                f"{self.name}: expected {self.n_shapes} shape coefficients, got {shape.shape}"
            )
        vertices = self.vertices + np.tensordot(shape, self.shape_units, axes=1)
        return replace(self, vertices=vertices)

    def feature_indices(self, names: list[str]) -> np.ndarray:
        missing = [n for n in names if n not in self.feature_points]
        if missing:
            raise FaceError(f"{self.name}: no feature point(s) {', '.join(missing)} on this model")
        return np.array([self.feature_points[n] for n in names], dtype=np.int64)


def default_model_path() -> Path:
    from uma.paths import codecs_dir

    return codecs_dir() / "face" / "uma-face.yaml"


def _units_to_yaml(names: tuple[str, ...], units: np.ndarray) -> list[dict]:
    out = []
    for name, unit in zip(names, units, strict=True):
        moved = np.flatnonzero(np.any(unit != 0, axis=1))
        out.append(
            {"name": name, "deltas": {int(i): [round(float(v), 5) for v in unit[i]] for i in moved}}
        )
    return out


def save_model(model: FaceModel, path: str | Path) -> None:
    """Write `model` as uma's face YAML (atomically)."""
    import yaml

    from uma.atomic import atomic_write_text

    data = {
        "name": model.name,
        "units": "model coordinates: x right, y up, z toward the camera; face ~2 tall",
        "vertices": [[round(float(v), 5) for v in row] for row in model.vertices],
        "triangles": [[int(v) for v in row] for row in model.triangles],
        "feature_points": {k: int(v) for k, v in sorted(model.feature_points.items())},
        "shape_units": _units_to_yaml(model.shape_unit_names, model.shape_units),
        "action_units": _units_to_yaml(model.action_unit_names, model.action_units),
    }
    atomic_write_text(
        path, yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=100)
    )


def _units_from_yaml(items, n: int, where: str) -> tuple[tuple[str, ...], np.ndarray]:
    if not isinstance(items, list):
        raise FaceError(f"{where}: expected a list of units")
    names, arrays = [], []
    for k, item in enumerate(items):
        try:
            unit = np.zeros((n, 3))
            for index, delta in item["deltas"].items():
                if int(index) < 0:
                    raise IndexError(f"vertex {index}")
                unit[int(index)] = [float(v) for v in delta]
            names.append(str(item["name"]))
            if not np.all(np.isfinite(unit)):
                raise ValueError("a delta is not finite")
        except (KeyError, TypeError, ValueError, IndexError, AttributeError) as err:
            raise FaceError(
                f"{where}[{k}]: expected name and deltas {{vertex: [dx, dy, dz]}} ({err})"
            ) from None
        arrays.append(unit)
    return tuple(names), np.array(arrays).reshape(-1, n, 3)


def read_model_yaml(path: str | Path) -> FaceModel:
    """Read a face model in uma's YAML."""
    from uma.face.yaml_text import read_yaml

    path = Path(path)
    data, _ = read_yaml(path, what="face model file")
    if not isinstance(data, dict):
        raise FaceError(f"{path}: expected a mapping with vertices, triangles, units")
    try:
        vertices = np.array(data["vertices"], dtype=np.float64)
        triangles = np.array(data["triangles"], dtype=np.int32)
        points = {str(k): int(v) for k, v in data.get("feature_points", {}).items()}
    except (KeyError, TypeError, ValueError, AttributeError) as err:
        raise FaceError(
            f"{path}: expected vertices and triangles as lists of triples and feature_points "
            f"as {{name: vertex}} ({err})"
        ) from None
    if not np.all(np.isfinite(vertices)):
        raise FaceError(f"{path}: vertices: expected finite numbers, got NaN or infinity")
    n = vertices.shape[0] if vertices.ndim == 2 else 0
    shape_names, shape_units = _units_from_yaml(
        data.get("shape_units", []), n, f"{path}: shape_units"
    )
    action_names, action_units = _units_from_yaml(
        data.get("action_units", []), n, f"{path}: action_units"
    )
    try:
        return FaceModel(
            name=str(data.get("name", path.stem)),
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
