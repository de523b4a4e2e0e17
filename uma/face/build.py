"""Build uma's generic wireframe and write it to `codecs/face/uma-face.yaml`.

Run `python -m uma.face.build` to regenerate the file (a test checks the two agree).

Units: model coordinates (x to the viewer's right, y up, z toward the camera; chin at y = -0.82).
The face is laid out from landmark positions of an average adult face (eyes at mid-height, a
face about 1.4 wide and 1.9 tall, a unit being about 10 cm), triangulated by Delaunay in the frontal plane, and given
depth by an ellipsoidal head with a protruding nose and lips and recessed eye sockets. The
person's own proportions come from the shape units; expression from the action units.
"""

from __future__ import annotations

import numpy as np

from uma.face.layout import FACE_POINTS as _HALF
from uma.face.layout import MPEG4_POINTS as _MPEG4
from uma.face.model import FaceModel, default_model_path, save_model

__all__ = ["build_wireframe", "main"]


def _depth(x: np.ndarray, y: np.ndarray, names: list[str]) -> np.ndarray:
    # An ellipsoidal head: the cheeks fall back toward the contour.
    z = 0.55 * np.sqrt(np.clip(1.0 - (x / 0.78) ** 2 - (y / 1.5) ** 2, 0.0, None)) - 0.25
    bump = {
        "nose_tip": 0.30,
        "nose_bridge": 0.16,
        "nose_bridge_top": 0.08,
        "subnasale": 0.18,
        "nose_side": 0.10,
        "nose_side_top": 0.06,
        "nostril_wing": 0.10,
        "nostril": 0.15,
        "upper_lip_top": 0.10,
        "upper_lip_side": 0.08,
        "upper_lip_inner": 0.08,
        "upper_lip_inner_side": 0.06,
        "lower_lip_inner": 0.08,
        "lower_lip_inner_side": 0.06,
        "lower_lip_bottom": 0.08,
        "lower_lip_side": 0.06,
        "chin": 0.06,
        "pupil": -0.02,
        "eye_inner": -0.06,
        "eyelid_upper": -0.02,
        "eyelid_lower": -0.03,
        "eye_outer": -0.05,
        "glabella": 0.03,
    }
    return z + np.array([bump.get(n, 0.0) for n in names])


def _points() -> tuple[list[str], np.ndarray]:
    names, xy = [], []
    for name, (x, y) in _HALF.items():
        if x == 0.0:
            names.append(name)
            xy.append((0.0, y))
        else:
            names.append(name + "_l")
            xy.append((x, y))
            names.append(name + "_r")
            xy.append((-x, y))
    return names, np.array(xy)


def _triangulate(xy: np.ndarray) -> np.ndarray:
    from scipy.spatial import Delaunay

    triangles = Delaunay(xy).simplices.astype(np.int32)
    # Counter-clockwise in the frontal view (x right, y up).
    a, b, c = xy[triangles[:, 0]], xy[triangles[:, 1]], xy[triangles[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    triangles[cross < 0] = triangles[cross < 0][:, [0, 2, 1]]
    # Drop slivers along the convex hull that no face surface needs.
    area = np.abs(cross) / 2
    return triangles[area > 1e-4]


def _unit(
    names: list[str], moves: dict[str, tuple[float, float, float]], *, mirror_x: bool = True
) -> np.ndarray:
    unit = np.zeros((len(names), 3))
    index = {n: i for i, n in enumerate(names)}
    for name, (dx, dy, dz) in moves.items():
        if name in index:
            unit[index[name]] = (dx, dy, dz)
            continue
        unit[index[name + "_l"]] = (dx, dy, dz)
        unit[index[name + "_r"]] = (-dx if mirror_x else dx, dy, dz)
    return unit


def _soften(unit: np.ndarray, triangles: np.ndarray, *, share: float = 0.5) -> np.ndarray:
    """`unit` with each unmoved vertex next to moved ones moved by `share` of their mean."""
    moved = np.any(unit != 0, axis=1)
    total = np.zeros_like(unit)
    count = np.zeros(len(unit))
    for a, b in np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]):
        for src, dst in ((a, b), (b, a)):
            if moved[src] and not moved[dst]:
                total[dst] += unit[src]
                count[dst] += 1
    out = unit.copy()
    ring = count > 0
    out[ring] = share * total[ring] / count[ring, None]
    return out


def _group(prefixes: list[str], delta: tuple[float, float, float], names: list[str]) -> dict:
    moves = {}
    for name in names:
        base = name[:-2] if name.endswith(("_l", "_r")) else name
        if base in prefixes:
            moves[base] = delta
    return moves


# Vertex groups the units move together.
_EYE = [
    "eye_inner",
    "eyelid_upper",
    "eye_outer",
    "eyelid_lower",
    "pupil",
    "eyelid_upper_inner",
    "eyelid_upper_outer",
]
_BROW = ["brow_inner", "brow_mid", "brow_outer"]
_MOUTH = [
    "lip_corner",
    "upper_lip_side",
    "upper_lip_inner_side",
    "lower_lip_inner_side",
    "lower_lip_side",
    "upper_lip_top",
    "upper_lip_inner",
    "lower_lip_inner",
    "lower_lip_bottom",
]
_NOSE = ["nose_tip", "subnasale", "nose_side", "nostril_wing", "nostril", "nose_bridge"]
_LOWER = [
    "chin_bottom",
    "chin",
    "mentolabial",
    "chin_side",
    "chin_inner",
    "jaw_chin",
    "jaw_mid",
    "jaw_low",
]
_CONTOUR = [
    "temple",
    "contour_brow",
    "contour_eye",
    "contour_cheek",
    "jaw_corner",
    "jaw_low",
    "cheek_outer",
    "cheekbone",
]


def _shape_units(names: list[str]) -> dict[str, np.ndarray]:
    """The shape units (personal proportions), before `_soften`."""
    shape_units = {
        "head_height": _unit(
            names,
            _group(
                ["forehead_top", "temple_top", "forehead_mid", "forehead_side", "forehead_outer"],
                (0, 0.1, 0),
                names,
            )
            | _group(_LOWER, (0, -0.1, 0), names),
        ),
        "face_width": _unit(names, _group(_CONTOUR, (0.1, 0, 0), names)),
        "eyebrows_vertical": _unit(names, _group(_BROW, (0, 0.1, 0), names)),
        "eyes_vertical": _unit(names, _group(_EYE, (0, 0.1, 0), names)),
        "eye_separation": _unit(names, _group(_EYE, (0.1, 0, 0), names)),
        "eyes_width": _unit(
            names,
            {
                "eye_inner": (-0.05, 0, 0),
                "eye_outer": (0.05, 0, 0),
                "eyelid_upper_inner": (-0.025, 0, 0),
                "eyelid_upper_outer": (0.025, 0, 0),
            },
        ),
        "nose_vertical": _unit(names, _group(_NOSE, (0, 0.1, 0), names)),
        "mouth_vertical": _unit(names, _group(_MOUTH, (0, 0.1, 0), names)),
        "mouth_width": _unit(
            names,
            {
                "lip_corner": (0.1, 0, 0),
                "upper_lip_side": (0.05, 0, 0),
                "lower_lip_side": (0.05, 0, 0),
                "upper_lip_inner_side": (0.05, 0, 0),
                "lower_lip_inner_side": (0.05, 0, 0),
                "nasolabial": (0.05, 0, 0),
            },
        ),
        "chin_width": _unit(
            names,
            {
                "jaw_chin": (0.1, 0, 0),
                "chin_side": (0.07, 0, 0),
                "chin_inner": (0.05, 0, 0),
                "jaw_mid": (0.05, 0, 0),
            },
        ),
    }
    return shape_units


def _jaw(names: list[str]) -> dict:
    """What the jaw drop moves, and how far."""
    jaw = _group(
        [
            "lower_lip_inner",
            "lower_lip_inner_side",
            "lower_lip_bottom",
            "lower_lip_side",
            "mentolabial",
            "chin",
            "chin_bottom",
            "chin_side",
            "chin_inner",
            "jaw_chin",
            "jaw_mid",
        ],
        (0, -0.18, -0.04),
        names,
    )
    jaw |= {
        "lip_corner": (0, -0.07, -0.02),
        "jaw_low": (0, -0.11, -0.03),
        "cheek_low": (0, -0.04, 0),
    }
    return jaw


def _action_units(names: list[str]) -> dict[str, np.ndarray]:
    """The action units (expressions)."""
    jaw = _jaw(names)
    action_units = {
        "jaw_drop": _unit(names, jaw),
        "lip_stretch": _unit(
            names,
            {
                "lip_corner": (0.08, 0, -0.02),
                "upper_lip_side": (0.04, 0, 0),
                "lower_lip_side": (0.04, 0, 0),
                "upper_lip_inner_side": (0.04, 0, 0),
                "lower_lip_inner_side": (0.04, 0, 0),
            },
        ),
        "lip_corner_depressor": _unit(
            names, {"lip_corner": (0, -0.08, 0), "lower_lip_side": (0, -0.03, 0)}
        ),
        "lip_corner_raiser": _unit(
            names,
            {
                "lip_corner": (0.04, 0.08, -0.02),
                "nasolabial": (0.02, 0.03, 0),
                "cheek": (0, 0.03, 0.01),
            },
        ),
        "upper_lip_raiser": _unit(
            names,
            {
                "upper_lip_top": (0, 0.06, 0.02),
                "upper_lip_side": (0, 0.05, 0.02),
                "upper_lip_inner": (0, 0.06, 0.02),
                "upper_lip_inner_side": (0, 0.05, 0.02),
            },
        ),
        "brow_raise": _unit(
            names, _group(_BROW, (0, 0.1, 0), names) | {"eyelid_upper": (0, 0.02, 0)}
        ),
        # Closed (1.0), the upper lid lies just above the lower one, pupil between: the lid comes
        # down without crossing the edges that span the eye, so no triangle folds over.
        "eye_close": _unit(
            names,
            {
                "eyelid_upper": (0, -0.09, 0.01),
                "eyelid_upper_inner": (0, -0.065, 0.01),
                "eyelid_upper_outer": (0, -0.065, 0.01),
                "pupil": (0, -0.04, 0),
            },
        ),
    }
    return action_units


def build_wireframe() -> FaceModel:
    """uma's generic face: ~70 vertices, ~120 triangles, 9 shape and 7 action units."""
    names, xy = _points()
    vertices = np.column_stack(
        [
            xy,
            _depth(
                xy[:, 0],
                xy[:, 1],
                [n.rsplit("_", 1)[0] if n.endswith(("_l", "_r")) else n for n in names],
            ),
        ]
    )
    triangles = _triangulate(xy)
    shape_units = _shape_units(names)
    action_units = _action_units(names)
    # A shape unit also carries the ring of vertices around the ones it names, half as far, so
    # a strong personal proportion bends the mesh instead of folding triangles over.
    shape_units = {k: _soften(unit, triangles) for k, unit in shape_units.items()}
    index = {n: i for i, n in enumerate(names)}
    points = {}
    for fp, (base, side) in _MPEG4.items():
        points[fp] = index[base if side == "m" else f"{base}_{side}"]
    return FaceModel(
        name="uma-face",
        vertices=vertices,
        triangles=triangles,
        shape_units=np.array(list(shape_units.values())),
        shape_unit_names=tuple(shape_units),
        action_units=np.array(list(action_units.values())),
        action_unit_names=tuple(action_units),
        feature_points=points,
    )


def main() -> None:
    model = build_wireframe()
    save_model(model, default_model_path())
    print(
        f"wrote {default_model_path()}: {model.n_vertices} vertices, {len(model.triangles)} triangles"
    )


if __name__ == "__main__":
    main()
