"""Reading a content description file (`.face`, as `ContentDescription.save` writes it).

Every array and metadata field is checked for type, shape and finiteness before a model is
built from it, so a damaged or foreign file fails with one line naming the file and the field
(`PATH: params: expected 13 finite numbers, got NaN at [0]`), never a numerical warning or a
message about something downstream.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from uma.errors import FaceError
from uma.face.describe import ContentDescription
from uma.face.geometry import N_POSE
from uma.face.image_bytes import decode_image
from uma.face.model import FaceModel
from uma.face.npz import read_npz

__all__ = ["load_description"]

WHAT = "a uma content description"
MEMBERS = ("meta", "vertices", "triangles", "action_units", "params", "shape", "texture_jpeg")


def load_description(path: str | Path) -> ContentDescription:
    """Read a description written by `ContentDescription.save`; anything else (truncated,
    damaged, foreign, NaN) is a one-line `FaceError` naming the file and the field."""
    path = Path(path)
    arrays = read_npz(path, what=WHAT, names=MEMBERS)
    meta = _meta(arrays["meta"], f"{path}: meta")
    vertices, triangles, actions = _mesh(arrays, meta, path)
    n, names = vertices.shape[0], meta["action_unit_names"]
    params = _floats(arrays["params"], f"{path}: params", ndim=1)
    if params.shape != (N_POSE + len(names),):
        raise FaceError(
            f"{path}: params: expected {N_POSE + len(names)} parameters ({N_POSE} pose + "
            f"{len(names)} action units), got {params.size}"
        )
    if not params[2] > 0:
        raise FaceError(f"{path}: params: expected a positive scale_px [2], got {params[2]}")
    shape = _floats(arrays["shape"], f"{path}: shape", ndim=1)
    texture = _texture(arrays["texture_jpeg"], f"{path}: texture_jpeg")
    try:
        model = FaceModel(
            name=meta["name"],
            vertices=vertices,
            triangles=triangles.astype(np.int32),
            shape_units=np.zeros((0, n, 3)),
            shape_unit_names=(),
            action_units=actions,
            action_unit_names=tuple(names),
            feature_points=meta["feature_points"],
        )
    except FaceError as err:
        raise FaceError(f"{path}: {err}") from None
    return ContentDescription(
        model=model,
        texture=texture,
        params=params,
        shape=shape,
        points=meta["points"],
        fit_rms_px=meta["fit_rms_px"],
        origin_px=meta["origin_px"],
        head_ring_outlines=meta["head_ring_outlines"],
    )


def _mesh(arrays, meta: dict, path: Path):
    """(vertices, triangles, action units) of a description's arrays, checked against each
    other and against the feature points `meta` names."""
    vertices = _floats(arrays["vertices"], f"{path}: vertices", ndim=2)
    if vertices.shape[1:] != (3,) or vertices.shape[0] < 3:
        raise FaceError(f"{path}: vertices: expected (N >= 3, 3) numbers, got {vertices.shape}")
    n = vertices.shape[0]
    triangles = arrays["triangles"]
    if triangles.dtype.kind not in "iu" or triangles.ndim != 2 or triangles.shape[1:] != (3,):
        raise FaceError(
            f"{path}: triangles: expected (T, 3) whole numbers, got {triangles.dtype} "
            f"{triangles.shape}"
        )
    if triangles.size == 0 or triangles.min() < 0 or triangles.max() >= n:
        raise FaceError(f"{path}: triangles: expected vertex numbers 0-{n - 1}, got others")
    names = meta["action_unit_names"]
    actions = _floats(arrays["action_units"], f"{path}: action_units", ndim=3)
    if actions.shape != (len(names), n, 3):
        raise FaceError(
            f"{path}: action_units: expected ({len(names)}, {n}, 3) for {len(names)} named units "
            f"and {n} vertices, got {actions.shape}"
        )
    for point, index in meta["feature_points"].items():
        if not 0 <= index < n:
            raise FaceError(
                f"{path}: meta.feature_points.{_key(point)}: expected a vertex 0-{n - 1}, got {index}"
            )
    return vertices, triangles, actions


def _floats(array: np.ndarray, where: str, *, ndim: int) -> np.ndarray:
    if array.dtype.kind not in "iuf" or array.ndim != ndim:
        raise FaceError(
            f"{where}: expected a {ndim}-d array of numbers, got {array.dtype} {array.shape}"
        )
    out = array.astype(np.float64)
    bad = np.argwhere(~np.isfinite(out))
    if bad.size:
        at = ", ".join(str(int(i)) for i in bad[0])
        raise FaceError(f"{where}: expected finite numbers, got {out[tuple(bad[0])]} at [{at}]")
    return out


def _texture(array: np.ndarray, where: str) -> np.ndarray:
    import cv2

    if array.dtype != np.uint8 or array.ndim != 1 or array.size == 0:
        raise FaceError(f"{where}: expected JPEG bytes, got {array.dtype} {array.shape}")
    image = decode_image(array, cv2.IMREAD_UNCHANGED)
    if image is None or image.ndim not in (2, 3) or min(image.shape[:2]) < 1:
        raise FaceError(f"{where}: expected a JPEG image, got {array.size} undecodable bytes")
    return image


def _meta(array: np.ndarray, where: str) -> dict[str, Any]:
    """The JSON metadata, every field checked."""
    if array.dtype != np.uint8 or array.ndim != 1:
        raise FaceError(f"{where}: expected UTF-8 JSON bytes, got {array.dtype} {array.shape}")
    try:
        meta = json.loads(array.tobytes().decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as err:
        raise FaceError(f"{where}: expected a JSON object, got unreadable text ({err})") from None
    if not isinstance(meta, dict):
        raise FaceError(f"{where}: expected a JSON object, got {type(meta).__name__}")

    def field(key: str, kind: type | tuple[type, ...], text: str):
        value = meta.get(key)
        if not isinstance(value, kind) or isinstance(value, bool):
            raise FaceError(f"{where}.{key}: expected {text}, got {_short(value)}")
        return value

    name = field("name", str, "a name")
    if not name.strip() or "\n" in name or "\r" in name:
        raise FaceError(f"{where}.name: expected a one-line, non-empty name, got {_short(name)}")
    names = field("action_unit_names", list, "a list of names")
    if not all(isinstance(n, str) for n in names):
        raise FaceError(f"{where}.action_unit_names: expected names, got {_short(names)}")
    feature_points = field("feature_points", dict, "a mapping of point names to vertices")
    for key, value in feature_points.items():
        if not isinstance(value, int) or isinstance(value, bool):
            raise FaceError(
                f"{where}.feature_points.{_key(key)}: expected a vertex number, got {_short(value)}"
            )
    points = {}
    for key, value in field("points", dict, "a mapping of point names to [x, y]").items():
        points[key] = _pair(value, f"{where}.points.{_key(key)}")
    rms = field("fit_rms_px", (int, float), "a number of pixels")
    if not (np.isfinite(rms) and rms >= 0):
        raise FaceError(f"{where}.fit_rms_px: expected a finite number >= 0, got {rms}")
    origin = _pair(meta.get("origin_px", [0.0, 0.0]), f"{where}.origin_px")
    ring = meta.get("head_ring_outlines")
    if ring is not None and not (
        isinstance(ring, int | float) and not isinstance(ring, bool) and 1 < ring <= 8
    ):
        raise FaceError(
            f"{where}.head_ring_outlines: expected a number above 1 and at most 8 (face-outline "
            f"radii), got {_short(ring)}"
        )
    return {
        "name": name,
        "action_unit_names": names,
        "feature_points": feature_points,
        "points": points,
        "fit_rms_px": float(rms),
        "origin_px": origin,
        "head_ring_outlines": None if ring is None else float(ring),
    }


def _pair(value: Any, where: str) -> tuple[float, float]:
    ok = isinstance(value, list) and len(value) == 2
    ok = ok and all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
    if not ok or not all(np.isfinite(value)):
        raise FaceError(f"{where}: expected [x, y] finite pixels, got {_short(value)}")
    return float(value[0]), float(value[1])


def _short(value: Any, limit: int = 40) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _key(key: str) -> str:
    """A key as a message shows it: as it is when plain, else quoted (no newline escapes)."""
    return key if key.isprintable() and key.strip() == key and key else repr(key)
