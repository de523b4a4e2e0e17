"""Geometry of the wireframe: P' = G(L(S(P))), projection to pixels, back-face culling.

Units: model coordinates (x right, y up, z toward the camera); angles in radians; image
coordinates in pixels (x right, y down, (0, 0) the centre of the top-left pixel).

Parameter vectors, batched along leading axes, shape (..., 6 + A):
[tx_px, ty_px, scale_px, rx_rad, ry_rad, rz_rad, au_0, ..., au_{A-1}]. Shape units S are baked
into the model first (`FaceModel.personalised`); L adds action units; G rotates by
R = Rz @ Ry @ Rx, scales and translates. Weak perspective by default; with `focal_px` a full
perspective whose camera sits `focal_px / scale_px` model units in front of the face.
"""

from __future__ import annotations

import numpy as np

from uma.face.model import FaceModel

__all__ = [
    "N_POSE",
    "POSE_NAMES",
    "rotation_matrix",
    "deform",
    "project",
    "visible_triangles",
    "facing_triangles",
    "make_params",
]

POSE_NAMES = ("tx_px", "ty_px", "scale_px", "rx_rad", "ry_rad", "rz_rad")
N_POSE = len(POSE_NAMES)


def make_params(
    model: FaceModel,
    *,
    tx_px: float,
    ty_px: float,
    scale_px: float,
    rx_rad: float = 0.0,
    ry_rad: float = 0.0,
    rz_rad: float = 0.0,
    actions: np.ndarray | None = None,
) -> np.ndarray:
    """A parameter vector (6 + A,) for `model`."""
    actions = (
        np.zeros(model.n_actions) if actions is None else np.asarray(actions, dtype=np.float64)
    )
    return np.concatenate([[tx_px, ty_px, scale_px, rx_rad, ry_rad, rz_rad], actions])


def rotation_matrix(rx: np.ndarray, ry: np.ndarray, rz: np.ndarray) -> np.ndarray:
    """R = Rz @ Ry @ Rx for batched angles; shape (..., 3, 3)."""
    rx, ry, rz = np.asarray(rx, float), np.asarray(ry, float), np.asarray(rz, float)
    if rx.ndim == ry.ndim == rz.ndim == 0:  # one pose: the same numbers, without the batch's
        return _one_rotation(rx, ry, rz)  # indexing (a drawing projects several times)
    rx, ry, rz = np.broadcast_arrays(rx, ry, rz)
    cx, sx, cy, sy, cz, sz = np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry), np.cos(rz), np.sin(rz)
    r = np.empty(rx.shape + (3, 3))
    r[..., 0, 0] = cz * cy
    r[..., 0, 1] = cz * sy * sx - sz * cx
    r[..., 0, 2] = cz * sy * cx + sz * sx
    r[..., 1, 0] = sz * cy
    r[..., 1, 1] = sz * sy * sx + cz * cx
    r[..., 1, 2] = sz * sy * cx - cz * sx
    r[..., 2, 0] = -sy
    r[..., 2, 1] = cy * sx
    r[..., 2, 2] = cy * cx
    return r


def _one_rotation(rx: np.ndarray, ry: np.ndarray, rz: np.ndarray) -> np.ndarray:
    """`rotation_matrix` of one pose (0-d angles): the same sines and cosines and the same
    products in the same order, on scalars (IEEE doubles either way: the same to the bit)."""
    cx, sx, cy, sy, cz, sz = np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry), np.cos(rz), np.sin(rz)
    return np.array(
        [
            [cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
            [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
            [-sy, cy * sx, cy * cx],
        ],
        dtype=np.float64,
    )


def deform(model: FaceModel, actions: np.ndarray) -> np.ndarray:
    """L(S(P)): vertices moved by the action units; (..., A) -> (..., N, 3)."""
    actions = np.asarray(actions, dtype=np.float64)
    if model.n_actions == 0:
        return np.broadcast_to(model.vertices, actions.shape[:-1] + model.vertices.shape).copy()
    return model.vertices + np.tensordot(actions, model.action_units, axes=([-1], [0]))


def _rotated(model: FaceModel, params: np.ndarray) -> np.ndarray:
    points = deform(model, params[..., N_POSE:])
    rotation = rotation_matrix(params[..., 3], params[..., 4], params[..., 5])
    return np.einsum("...ij,...nj->...ni", rotation, points)


def project(model: FaceModel, params: np.ndarray, *, focal_px: float | None = None) -> np.ndarray:
    """Pixel positions of every vertex; (..., 6 + A) -> (..., N, 2)."""
    params = np.asarray(params, dtype=np.float64)
    if params.shape[-1] != N_POSE + model.n_actions:
        raise ValueError(f"expected {N_POSE + model.n_actions} parameters, got {params.shape[-1]}")
    rotated = _rotated(model, params)
    scale = params[..., 2, None]
    factor = scale
    if focal_px is not None:
        # The nearer a point (larger z), the larger it appears.
        factor = scale * focal_px / (focal_px - scale * rotated[..., 2])
    x = params[..., 0, None] + factor * rotated[..., 0]
    y = params[..., 1, None] - factor * rotated[..., 1]
    return np.stack([x, y], axis=-1)


def visible_triangles(
    model: FaceModel, params: np.ndarray, *, focal_px: float | None = None
) -> np.ndarray:
    """Triangles facing the camera at `params` (6 + A,): counter-clockwise seen from the front."""
    return facing_triangles(model, project(model, params, focal_px=focal_px))


def facing_triangles(model: FaceModel, points: np.ndarray) -> np.ndarray:
    """`visible_triangles` from the vertices already projected (`project`'s (..., N, 2)): a
    caller that needs the projection too projects once."""
    a, b, c = (points[..., model.triangles[:, k], :] for k in range(3))
    # In image coordinates (y down) a front-facing counter-clockwise triangle turns clockwise.
    cross = (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (
        c[..., 0] - a[..., 0]
    )
    return cross < 0
