"""The whole picture as one mesh: the face wireframe, a head ring around it and a fixed far ring.

Units: model coordinates for the face and head ring (x right, y up, z toward the camera);
pixels for the far ring and every projected point.

Texture-mapping only the face over a still photograph leaves seams where the moved face meets
the unmoved hair, ears and neck. Here a ring of vertices around the face outline (the outline
scaled by `HEAD_RING_SCALE` about its centre, set a little behind it) moves rigidly with the head
and carries hair, ears and neck; a far ring, fixed in the image well outside the frame, holds
the background still. Strips of triangles join outline to head ring and head ring to far ring,
so every pixel of the frame is a continuous piecewise-affine warp of the template: the face
animates, the head around it follows, and the displacement fades out toward the frame's edges.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.face.geometry import N_POSE, project, rotation_matrix
from uma.face.model import FaceModel

__all__ = ["SceneMesh", "boundary_loop", "vertex_normals", "HEAD_RING_SCALE"]

HEAD_RING_SCALE = 1.4  # head ring radius / face outline radius, about the outline's centre
HEAD_RING_DEPTH = 0.15  # model units the head ring sits behind the outline
FAR_RING_SCALE = 1.5  # far ring radius / frame diagonal


def boundary_loop(triangles: np.ndarray) -> np.ndarray:
    """The outline's vertices in order, counter-clockwise seen from the front (as the triangles)."""
    tri = np.asarray(triangles)
    pairs = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    directed = {(int(a), int(b)) for a, b in pairs}
    following = {a: b for a, b in directed if (b, a) not in directed}
    if not following:
        raise ValueError("the mesh has no outline (closed surface?)")
    start = min(following)
    loop = [start]
    while (nxt := following[loop[-1]]) != start:
        if len(loop) > len(following):
            raise ValueError("the mesh outline is not one simple loop")
        loop.append(nxt)
    if len(loop) != len(following):
        raise ValueError("the mesh outline is not one simple loop (holes or islands)")
    return np.array(loop, dtype=np.int64)


def vertex_normals(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Unit normals (N, 3): the area-weighted mean of the adjoining triangles' normals."""
    a, b, c = (vertices[..., triangles[:, k], :] for k in range(3))
    # Counter-clockwise seen from the front, so the cross product points toward the camera; its
    # length is twice the area, which weights the mean.
    faces = np.cross(b - a, c - a)
    normals = np.zeros(vertices.shape)
    for k in range(3):
        np.add.at(normals, (..., triangles[:, k], slice(None)), faces)
    length = np.linalg.norm(normals, axis=-1, keepdims=True)
    return normals / np.where(length > 0, length, 1.0)


@dataclass(frozen=True, eq=False)
class SceneMesh:
    """Face, head ring and far ring for one personal model on one frame size."""

    model: FaceModel
    outline: np.ndarray  # (M,) face vertex numbers, counter-clockwise
    head_ring: np.ndarray  # (M, 3) model coordinates
    far_ring_px: np.ndarray  # (M, 2) fixed image points
    triangles: np.ndarray  # (T_face + 4M, 3): background strips first, then the face

    @classmethod
    def build(
        cls,
        model: FaceModel,
        template_params: np.ndarray,
        shape: tuple[int, int],
        *,
        far_ring_scale: float | None = None,
        head_ring_scale: float = HEAD_RING_SCALE,
    ) -> SceneMesh:
        """Rings placed from the face at `template_params` in a frame of `shape` (H, W). With
        `far_ring_scale` the far ring lies at that many head-ring radii from the face's centre
        (so the picture beyond it stays still) instead of `FAR_RING_SCALE` frame diagonals;
        `head_ring_scale` sizes the head ring against the outline (`HEAD_RING_SCALE`)."""
        outline = boundary_loop(model.triangles)
        rim = model.vertices[outline]
        centre = rim[:, :2].mean(axis=0)
        head_ring = np.column_stack(
            [centre + head_ring_scale * (rim[:, :2] - centre), rim[:, 2] - HEAD_RING_DEPTH]
        )
        # Far ring: along the directions from the face's centre to the head ring, in the image.
        ring_px = _project_points(head_ring, template_params)
        centre_px = ring_px.mean(axis=0)
        direction = ring_px - centre_px
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        radius_px = FAR_RING_SCALE * float(np.hypot(*shape))
        if far_ring_scale is not None:
            head_px = np.linalg.norm(ring_px - centre_px, axis=1)
            radius_px = far_ring_scale * head_px[:, None]
        far_ring_px = centre_px + radius_px * direction
        n, m = model.n_vertices, len(outline)
        i = np.arange(m)
        j = (i + 1) % m
        rim_i, rim_j = outline[i], outline[j]
        head_i, head_j = n + i, n + j
        far_i, far_j = n + m + i, n + m + j
        strips = np.concatenate(
            [
                np.column_stack([rim_i, head_i, head_j]),
                np.column_stack([rim_i, head_j, rim_j]),
                np.column_stack([head_i, far_i, far_j]),
                np.column_stack([head_i, far_j, head_j]),
            ]
        )
        triangles = np.concatenate([strips, model.triangles]).astype(np.int32)
        return cls(model, outline, head_ring, far_ring_px, triangles)

    @property
    def n_points(self) -> int:
        return self.model.n_vertices + 2 * len(self.outline)

    def points(self, params: np.ndarray) -> np.ndarray:
        """Every scene point in the image at `params` (6 + A,): face, head ring, far ring."""
        face = project(self.model, params)
        return np.concatenate([face, _project_points(self.head_ring, params), self.far_ring_px])

    def depth(self, params: np.ndarray) -> np.ndarray:
        """A drawing order for `rasterize`: background strips under the face, the face by z."""
        rotation = rotation_matrix(params[3], params[4], params[5])
        z = (self.model.vertices @ rotation.T)[:, 2]
        m = len(self.outline)
        return np.concatenate([z, np.full(m, -1e3), np.full(m, -1e6)])

    def normals(self, params: np.ndarray) -> np.ndarray:
        """Unit normals of the face vertices at `params` (N, 3), in camera coordinates."""
        from uma.face.geometry import deform

        vertices = deform(self.model, params[N_POSE:])
        rotation = rotation_matrix(params[3], params[4], params[5])
        return vertex_normals(vertices, self.model.triangles) @ rotation.T


def _project_points(points: np.ndarray, params: np.ndarray) -> np.ndarray:
    """Weak perspective of fixed model points (no action units) at `params`."""
    rotation = rotation_matrix(params[3], params[4], params[5])
    rotated = points @ rotation.T
    return np.column_stack(
        [params[0] + params[2] * rotated[:, 0], params[1] - params[2] * rotated[:, 1]]
    )
