"""The face's own luma over its box, as a `uma.mbc.scene_render.SceneRenderer` draws it: what
the encoder measures light against and what a receiver pastes from the description.

Units: pixels; parameters as in `uma.face.geometry`; luma uint8.

The model is projected once a call, or not at all when the renderer's layered drawing of the
same frame already did (`SceneRenderer.scene_points`): the box, the triangles facing the
camera and the labels all come from that one projection. Where the face reads from (the
reference's pose, or the description's when the face comes from it) changes only with a new
reference or face source, so its triangles' corners are gathered once for each and kept on
the renderer.
"""

from __future__ import annotations

import numpy as np

from uma.face.geometry import facing_triangles, project
from uma.face.render import barycentric_affine, triangle_labels
from uma.mbc.layered_kernels import FAR_OUTSIDE_MAP, triangle_maps

__all__ = ["face_luma"]


def _source_corners(renderer) -> tuple[np.ndarray, np.ndarray]:
    """(picture, (T, 2, 3) the face's triangles' corners where the face reads from): kept on
    the renderer until its reference or face source changes."""
    model = renderer.description.model
    face_source = renderer._face_source
    kept = renderer.__dict__.get("_face_corners")
    # The face source itself is kept with its key: its id cannot be reused while it is kept.
    key = (renderer.reference_serial, id(face_source))
    if kept is not None and kept[0] == key and kept[1] is face_source:
        return kept[2], kept[3]
    picture, source = renderer.reference, renderer._reference_points[: model.n_vertices]
    if face_source is not None:
        picture = face_source[0]
        source = project(model, face_source[1])
    corners = source[model.triangles].transpose(0, 2, 1)
    renderer._face_corners = (key, face_source, picture, corners)
    return picture, corners


def face_luma(renderer, params: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple[int, int]]:
    """The face's own luma at `params` without light, over its bounding box only: (patch,
    mask, (x0, y0) of the box); empty when the face lies outside the picture. The maps and
    picture read are left in `renderer._last_face` (the chroma a receiver pastes)."""
    import cv2

    model = renderer.description.model
    width, height = renderer.size
    kept = renderer.kept_points(params)  # the layered drawing's of this frame, if any
    target = project(model, params) if kept is None else kept[: model.n_vertices]
    x0, y0 = np.maximum(np.floor(target.min(axis=0)).astype(int), 0)
    x1 = min(int(np.ceil(target[:, 0].max())) + 1, width)
    y1 = min(int(np.ceil(target[:, 1].max())) + 1, height)
    if x1 <= x0 or y1 <= y0:
        return np.zeros((0, 0), np.uint8), np.zeros((0, 0), bool), (0, 0)
    local = target - (x0, y0)
    triangles = model.triangles
    labels = triangle_labels(
        local, triangles, (y1 - y0, x1 - x0), triangle_mask=facing_triangles(model, target)
    )
    picture, corners = _source_corners(renderer)
    # (T, 2, 3): the source's (x, y) as an affine function of the box's (x, y, 1); one
    # gather per coefficient (label -1: the last entry, far outside the picture).
    maps = np.matmul(corners, barycentric_affine(local, triangles))
    xs, ys = renderer._x[: y1 - y0, : x1 - x0], renderer._y[: y1 - y0, : x1 - x0]
    map_x, map_y = triangle_maps(labels, maps, FAR_OUTSIDE_MAP, xs, ys)
    patch = cv2.remap(
        picture[:height], map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
    )
    renderer._last_face = (map_x, map_y, picture)
    return patch, labels >= 0, (int(x0), int(y0))
