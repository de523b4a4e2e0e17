"""The layered scene drawn fast: plate, then torso and halo by whole-picture affine warps, then
the head by its mesh over the head's box only.

Units: pixels; pictures planar YUV 4:2:0 (H * 3 // 2, W) uint8; a chroma sample (i, j) sits
at luma position (2j + 0.5, 2i + 0.5).

The torso and the halo each move by one 2-D map (`uma.mbc.layers`), so OpenCV's `warpAffine`
draws them (no per-pixel maps); only the head needs a map per pixel, and only over its box.
A chroma sample takes the layer of either of its block's diagonal luma pixels (the head
first), the plate only where both lie behind the person, as the plate learns chroma.
"""

from __future__ import annotations

import numpy as np

from uma.mbc.layers import NO_BODY_MOTION, body_matrix, head_ring_points, rigid_fit

__all__ = ["compose_layers", "chroma_matrix"]

_GAP_KERNEL = np.ones((3, 3), np.uint8)
# A layer's edge fades over about this many pixels (the head's outward, into the picture moved
# with it; the torso's into the plate), fully once the layer has moved FEATHER_FULL_PX from the
# reference (not at all at the reference's pose: the identity returns the reference).
FEATHER_SIGMA_PX = 1.5
FEATHER_FULL_PX = 2.0


def chroma_matrix(matrix: np.ndarray) -> np.ndarray:
    """The 2x3 map `matrix` (luma pixels) on the half-size chroma planes."""
    out = np.array(matrix, dtype=np.float64)
    out[:, 2] = (matrix[:, :2] @ (0.5, 0.5) + matrix[:, 2] - 0.5) / 2.0
    return out


def _box(points: np.ndarray, size: tuple[int, int]) -> tuple[int, int, int, int] | None:
    """The even-cornered, even-sized box (x0, y0, x1, y1) around `points` in the picture."""
    width, height = size
    x0 = max(int(np.floor(points[:, 0].min())) - 1, 0) // 2 * 2
    y0 = max(int(np.floor(points[:, 1].min())) - 1, 0) // 2 * 2
    x1 = min((int(np.ceil(points[:, 0].max())) + 3) // 2 * 2, width)
    y1 = min((int(np.ceil(points[:, 1].max())) + 3) // 2 * 2, height)
    if x1 - x0 < 2 or y1 - y0 < 2:
        return None
    return x0, y0, x1, y1


def _head(renderer, params: np.ndarray, target: np.ndarray, box):
    """The head over `box`: its pixels' triangle labels and where they read the reference."""
    from uma.face.render import barycentric_affine, triangle_labels

    scene = renderer.scene
    x0, y0, x1, y1 = box
    labels = triangle_labels(
        target - (x0, y0),
        scene.triangles,
        (y1 - y0, x1 - x0),
        triangle_mask=renderer._drawn(target),
        depth=scene.depth(params),
    )
    affine = barycentric_affine(target, scene.triangles)
    coeffs = np.einsum("tjk,tjc->tck", affine, renderer._reference_points[scene.triangles])
    still = np.array([[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    table = np.concatenate([coeffs, still]).reshape(-1, 6).T.astype(np.float32)
    flat = np.where(labels < 0, len(coeffs), labels).ravel()
    c = [np.take(row, flat).reshape(labels.shape) for row in table]
    xs, ys = renderer._x[y0:y1, x0:x1], renderer._y[y0:y1, x0:x1]
    map_x = c[0] * xs + c[1] * ys + c[2]
    map_y = c[3] * xs + c[4] * ys + c[5]
    return labels, map_x, map_y


def compose_layers(renderer, params: np.ndarray, body: np.ndarray | None):
    """The picture (YUV 4:2:0, no light) of a layered `renderer`
    (`uma.mbc.scene_render.SceneRenderer`) at `params` with the torso at `body` (None:
    still), and the mask of the face's own pixels."""
    import cv2

    width, height = renderer.size
    size, half = (width, height), (width // 2, height // 2)
    scene, reference = renderer.scene, renderer.reference
    target = scene.points(params)
    torso_forward = body_matrix(NO_BODY_MOTION if body is None else body, renderer.anchor)
    head_forward = rigid_fit(renderer._reference_ring, head_ring_points(scene, target))
    out = renderer._plate_picture().copy()
    nearest, linear, edge = cv2.INTER_NEAREST, cv2.INTER_LINEAR, cv2.BORDER_REPLICATE
    torso = cv2.warpAffine(renderer._torso_below, torso_forward, size, flags=nearest)
    halo = cv2.warpAffine(renderer.halo_mask, head_forward, size, flags=nearest)
    head = np.zeros((height, width), np.uint8)
    face = np.zeros((height, width), bool)
    n_head = scene.model.n_vertices + len(scene.outline)
    box = _box(target[:n_head], size)
    if box is not None:
        x0, y0, x1, y1 = box
        labels, map_x, map_y = _head(renderer, params, target, box)
        head[y0:y1, x0:x1] = labels >= 0
        face[y0:y1, x0:x1] = labels >= renderer._strips
    # The mesh's edge and the halo's rigid motion part by a pixel here and there: close the
    # gap (it would show the plate as a dotted seam).
    halo = cv2.dilate(halo | head, _GAP_KERNEL) & (1 - head)
    torso &= 1 - (halo | head)
    luma = out[:height]
    chroma = out[height:].reshape(2, height // 2, width // 2)
    around, plate = None, None
    moved = _head_moved_px(renderer, target)
    body_moved = 0.0 if body is None else float(np.hypot(body[0], body[1]) + 100 * abs(body[2]))
    for mask, matrix in [(torso, torso_forward), (halo, head_forward)]:
        if mask is torso and body_moved > 0:
            plate = out.copy()  # the torso's edge fades into the plate
        if mask is halo:
            if plate is not None:  # the torso's outer edge only: it meets the head inside
                strength = min(body_moved / FEATHER_FULL_PX, 1.0)
                _feather(out, plate, torso.view(bool), strength, (torso | halo | head).view(bool))
            if moved > 0:  # the picture moved with the head: what the seam fades into
                around = np.empty_like(out)
        drawn = cv2.warpAffine(reference[:height], matrix, size, flags=linear, borderMode=edge)
        np.copyto(luma, drawn, where=mask.view(bool))
        if mask is halo and around is not None:
            around[:height] = drawn
        at = (mask[0::2, 0::2] | mask[1::2, 1::2]).view(bool)
        for k, (plane, source) in enumerate(zip(chroma, (renderer._u, renderer._v), strict=True)):
            drawn = cv2.warpAffine(source, chroma_matrix(matrix), half, flags=linear,
                                   borderMode=edge)  # fmt: skip
            np.copyto(plane, drawn, where=at)
            if mask is halo and around is not None:
                around[height:].reshape(2, height // 2, width // 2)[k] = drawn
    if box is not None:
        inside = head[y0:y1, x0:x1].view(bool)
        drawn = cv2.remap(reference[:height], map_x, map_y, linear, borderMode=edge)
        np.copyto(luma[y0:y1, x0:x1], drawn, where=inside)
        cx = (map_x[0::2, 0::2] + map_x[1::2, 1::2] - 1.0) * 0.25
        cy = (map_y[0::2, 0::2] + map_y[1::2, 1::2] - 1.0) * 0.25
        at = inside[0::2, 0::2] | inside[1::2, 1::2]
        for plane, source in zip(chroma, (renderer._u, renderer._v), strict=True):
            drawn = cv2.remap(source, cx, cy, linear, borderMode=edge)
            np.copyto(plane[y0 // 2 : y1 // 2, x0 // 2 : x1 // 2], drawn, where=at)
    if around is not None:
        _bleed(out, around, (halo | head).view(bool), min(moved / FEATHER_FULL_PX, 1.0))
    return out, face


def _bleed(out: np.ndarray, around: np.ndarray, mask: np.ndarray, strength: float) -> None:
    """Fade the head's edge outward: the pixels just outside `mask` (the head and its halo)
    in `out` move toward `around` (the picture moved rigidly with the head) by up to half,
    over about `FEATHER_SIGMA_PX`, times `strength`; the head's own pixels stay as drawn."""
    import cv2

    height = mask.shape[0]
    weight = strength * cv2.GaussianBlur(mask.astype(np.float32), (0, 0), FEATHER_SIGMA_PX)
    weight[mask] = 0.0
    half = weight[0::2, 0::2]
    for rows, w in ((slice(0, height), weight),
                    (slice(height, None), np.concatenate([half, half]).reshape(-1, out.shape[1]))):  # fmt: skip
        top, toward = out[rows].astype(np.float32), around[rows].astype(np.float32)
        out[rows] = np.clip(np.rint(top + w * (toward - top)), 0, 255)


def _head_moved_px(renderer, target: np.ndarray) -> float:
    """How far the head ring moved from the reference (the farthest point, pixels)."""
    ring = head_ring_points(renderer.scene, target)
    return float(np.max(np.hypot(*(ring - renderer._reference_ring).T)))


def _feather(
    out: np.ndarray, under: np.ndarray, mask: np.ndarray, strength: float, solid=None
) -> None:
    """Fade the pixels of `mask` in `out` into `under` near the edge of `solid` (default
    `mask`) over about `FEATHER_SIGMA_PX`, by `strength` (0: a hard edge, as when the layer has
    not moved)."""
    import cv2

    height = mask.shape[0]
    solid = mask if solid is None else solid
    inner = cv2.GaussianBlur(solid.astype(np.float32), (0, 0), FEATHER_SIGMA_PX)
    keep = 1.0 - strength * (1.0 - inner)
    keep[~mask] = 1.0
    for rows, weight in ((slice(0, height), keep), (slice(height, None), None)):
        if weight is None:
            half = keep[0::2, 0::2]
            weight = np.concatenate([half, half]).reshape(-1, out.shape[1])
        top, bottom = out[rows].astype(np.float32), under[rows].astype(np.float32)
        out[rows] = np.clip(np.rint(bottom + weight * (top - bottom)), 0, 255)
