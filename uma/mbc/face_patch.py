"""The face's own luma over its box, as `uma.mbc.scene_render.SceneRenderer` draws it: what the
encoder measures light against and what a receiver pastes from the description.

Units: pixels; parameters as in `uma.face.geometry`; luma uint8.

Pure: the renderer passes the model's projection at the pose (its layered drawing's of the
same frame when it has one, so the model is projected once a frame) and the corners of the
face's triangles where the face reads from (`face_corners`: they change only with a new
reference or face source, so the renderer keeps them); the box, the facing triangles and the
labels all come from the one projection.
"""

from __future__ import annotations

import numpy as np

from uma.face.geometry import facing_triangles
from uma.face.model import FaceModel
from uma.face.render import barycentric_affine, triangle_labels
from uma.mbc.layered_kernels import FAR_OUTSIDE_MAP, triangle_maps

__all__ = ["face_corners", "face_luma"]


def face_corners(model: FaceModel, source_points: np.ndarray) -> np.ndarray:
    """(T, 2, 3): each face triangle's corners (x row, y row) at `source_points` (N, 2), the
    model's vertices projected where the face reads from."""
    return source_points[model.triangles].transpose(0, 2, 1)


def face_luma(
    model: FaceModel,
    size: tuple[int, int],
    target: np.ndarray,
    picture: np.ndarray,
    corners: np.ndarray,
    grid: tuple[np.ndarray, np.ndarray],
):
    """(patch, mask, (x0, y0) of the box, (map_x, map_y, picture)): the face's luma without
    light over its bounding box, for the model's vertices projected at the pose (`target`, N
    x 2) in a picture of `size` (W, H), read from YUV 4:2:0 `picture` through `corners`
    (`face_corners`); `grid` is the renderer's pixel coordinates (xs, ys), at least the box.
    Empty, and no maps, when the face lies outside the picture."""
    import cv2

    width, height = size
    x0, y0 = np.maximum(np.floor(target.min(axis=0)).astype(int), 0)
    x1 = min(int(np.ceil(target[:, 0].max())) + 1, width)
    y1 = min(int(np.ceil(target[:, 1].max())) + 1, height)
    if x1 <= x0 or y1 <= y0:
        return np.zeros((0, 0), np.uint8), np.zeros((0, 0), bool), (0, 0), None
    local = target - (x0, y0)
    triangles = model.triangles
    labels = triangle_labels(
        local, triangles, (y1 - y0, x1 - x0), triangle_mask=facing_triangles(model, target)
    )
    # (T, 2, 3): the source's (x, y) as an affine function of the box's (x, y, 1); one
    # gather per coefficient (label -1: the last entry, far outside the picture).
    maps = np.matmul(corners, barycentric_affine(local, triangles))
    xs, ys = grid[0][: y1 - y0, : x1 - x0], grid[1][: y1 - y0, : x1 - x0]
    map_x, map_y = triangle_maps(labels, maps, FAR_OUTSIDE_MAP, xs, ys)
    patch = cv2.remap(
        picture[:height], map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
    )
    return patch, labels >= 0, (int(x0), int(y0)), (map_x, map_y, picture)
