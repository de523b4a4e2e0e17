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

from uma.mbc.layer_boxes import ONLY_MARGIN_PX, ONLY_MARGIN_SOFT_PX, mask_box
from uma.mbc.layer_boxes import clip_box as _clip_of
from uma.mbc.layer_boxes import crop as _crop
from uma.mbc.layer_boxes import points_box as _box
from uma.mbc.layer_boxes import within as _within
from uma.mbc.layered_kernels import (
    STILL_MAP,
    blend,
    copy_where,
    triangle_maps,
    zero_where,
)
from uma.mbc.layers import (
    N_BODY,
    N_TORSO,
    NO_BODY_MOTION,
    body_matrix,
    head_ring_points,
    rigid_fit,
    shift_yuv,
)
from uma.mbc.outline import soften_outline

__all__ = ["compose_layers", "chroma_matrix", "mask_box", "face_mask"]

_GAP_KERNEL = np.ones((3, 3), np.uint8)
# A layer's edge fades over about this many pixels (the head's outward, into the picture moved
# with it; the torso's into the plate), fully once the layer has moved FEATHER_FULL_PX from the
# reference (not at all at the reference's pose: the identity returns the reference).
FEATHER_SIGMA_PX = 1.5
FEATHER_FULL_PX = 2.0
# OpenCV's Gaussian at FEATHER_SIGMA_PX reaches 6 px: a box this much wider sees all of it.
_BLEED_MARGIN_PX = 8


def chroma_matrix(matrix: np.ndarray) -> np.ndarray:
    """The 2x3 map `matrix` (luma pixels) on the half-size chroma planes."""
    out = np.array(matrix, dtype=np.float64)
    out[:, 2] = (matrix[:, :2] @ (0.5, 0.5) + matrix[:, 2] - 0.5) / 2.0
    return out


def _head_labels(renderer, params: np.ndarray, target: np.ndarray, box) -> np.ndarray:
    """The head over `box`: its pixels' triangle labels (-1: none)."""
    from uma.face.render import triangle_labels

    scene = renderer.scene
    x0, y0, x1, y1 = box
    return triangle_labels(
        target - (x0, y0),
        scene.triangles,
        (y1 - y0, x1 - x0),
        triangle_mask=renderer._drawn(target),
        depth=scene.depth(params),
    )


def face_mask(renderer, params: np.ndarray) -> np.ndarray:
    """The mask (H, W bool) of the face's own pixels that `renderer` (a
    `uma.mbc.scene_render.SceneRenderer`) draws at `params` (the same labels), without
    drawing anything."""
    if not renderer.layered:
        return renderer.maps(params)[2]
    width, height = renderer.size
    scene = renderer.scene
    target = scene.points(params)
    face = np.zeros((height, width), bool)
    box = _box(target[: scene.model.n_vertices + len(scene.outline)], renderer.size)
    if box is not None:
        x0, y0, x1, y1 = box
        face[y0:y1, x0:x1] = _head_labels(renderer, params, target, box) >= renderer._strips
    return face


def _head_maps(renderer, labels: np.ndarray, target: np.ndarray, box, drawn):
    """Where the head's pixels of `drawn` (a box inside the head's `box`, whose `labels` they
    are) read the reference."""
    from uma.face.render import barycentric_affine

    scene = renderer.scene
    x0, y0, x1, y1 = drawn
    affine = barycentric_affine(target, scene.triangles)
    # (T, 2, 3): the reference's (x, y) as an affine function of the picture's (x, y, 1).
    coeffs = np.matmul(renderer._reference_points[scene.triangles].transpose(0, 2, 1), affine)
    xs, ys = renderer._x[y0:y1, x0:x1], renderer._y[y0:y1, x0:x1]
    labels = labels[y0 - box[1] : y1 - box[1], x0 - box[0] : x1 - box[0]]
    # Outside the head (label -1) a pixel reads the picture where it is.
    return triangle_maps(labels, coeffs, STILL_MAP, xs, ys)


def _shifted(matrix: np.ndarray, x0: int, y0: int) -> np.ndarray:
    """`matrix` drawing into a box whose corner is (x0, y0) instead of the whole picture."""
    out = np.array(matrix, dtype=np.float64)
    out[:, 2] -= (x0, y0)
    return out


def _warped_mask(source: np.ndarray, source_box, matrix: np.ndarray, size) -> np.ndarray:
    """The 0/1 mask `source` moved by `matrix` into a picture of `size` (W, H), warped over
    the box its moved bounding box `source_box` covers only."""
    import cv2

    width, height = size
    out = np.zeros((height, width), np.uint8)
    if source_box is None:
        return out
    x0, y0, x1, y1 = source_box
    corners = np.array([[x0, y0], [x1, y0], [x0, y1], [x1, y1]], np.float64)
    box = _box(corners @ matrix[:, :2].T + matrix[:, 2], size)
    if box is None:
        return out
    bx0, by0, bx1, by1 = box
    out[by0:by1, bx0:bx1] = cv2.warpAffine(
        source, _shifted(matrix, bx0, by0), (bx1 - bx0, by1 - by0), flags=cv2.INTER_NEAREST
    )
    return out


def _draw_layer(renderer, out: np.ndarray, mask: np.ndarray, matrix: np.ndarray, box, chroma=True):
    """Draw the reference moved by `matrix` into `out` where `mask`, over `box` only; the
    moved picture over `box` (luma rows, then both chroma planes' rows, left undrawn without
    `chroma`)."""
    import cv2

    height = renderer.size[1]
    x0, y0, x1, y1 = box
    linear, edge = cv2.INTER_LINEAR, cv2.BORDER_REPLICATE
    moved = _shifted(matrix, x0, y0)
    drawn = np.empty(((y1 - y0) * 3 // 2, x1 - x0), np.uint8)
    drawn[: y1 - y0] = cv2.warpAffine(
        renderer.reference[:height], moved, (x1 - x0, y1 - y0), flags=linear, borderMode=edge
    )
    inside = mask[y0:y1, x0:x1]
    copy_where(out[y0:y1, x0:x1], drawn[: y1 - y0], inside)
    if not chroma:
        return drawn
    at = (inside[0::2, 0::2] | inside[1::2, 1::2]).view(bool)
    half = ((x1 - x0) // 2, (y1 - y0) // 2)
    planes = out[height:].reshape(2, height // 2, -1)
    below = drawn[y1 - y0 :].reshape(2, half[1], half[0])
    for k, source in enumerate((renderer._u, renderer._v)):
        below[k] = cv2.warpAffine(source, chroma_matrix(moved), half, flags=linear,
                                  borderMode=edge)  # fmt: skip
        copy_where(planes[k][y0 // 2 : y1 // 2, x0 // 2 : x1 // 2], below[k], at)
    return drawn


def _draw_head(renderer, out: np.ndarray, inside: np.ndarray, maps, box, chroma=True) -> None:
    """Draw the head over `box` where `inside`, reading the reference at `maps` (its chroma
    too with `chroma`)."""
    import cv2

    height = renderer.size[1]
    x0, y0, x1, y1 = box
    map_x, map_y = maps
    linear, edge = cv2.INTER_LINEAR, cv2.BORDER_REPLICATE
    drawn = cv2.remap(renderer.reference[:height], map_x, map_y, linear, borderMode=edge)
    copy_where(out[y0:y1, x0:x1], drawn, inside)
    if not chroma:
        return
    cx = (map_x[0::2, 0::2] + map_x[1::2, 1::2] - 1.0) * 0.25
    cy = (map_y[0::2, 0::2] + map_y[1::2, 1::2] - 1.0) * 0.25
    at = inside[0::2, 0::2] | inside[1::2, 1::2]
    planes = out[height:].reshape(2, height // 2, -1)
    for plane, source in zip(planes, (renderer._u, renderer._v), strict=True):
        drawn = cv2.remap(source, cx, cy, linear, borderMode=edge)
        copy_where(plane[y0 // 2 : y1 // 2, x0 // 2 : x1 // 2], drawn, at)


def compose_layers(
    renderer, params: np.ndarray, body: np.ndarray | None, chroma: bool = True, only=None
):
    """The picture (YUV 4:2:0, no light) of a layered `renderer`
    (`uma.mbc.scene_render.SceneRenderer`) at `params` with the torso at `body` (None:
    still), and the mask of the face's own pixels; without `chroma` its chroma planes are
    not drawn (they hold no picture), its luma the same. `only` (luma only): a function of
    the face's mask giving the box (x0, y0, x1, y1) its caller reads (None: all); the luma
    is then the same inside that box and the face's mask everywhere, the rest of the
    picture holds whatever each layer's box, cut to that box and a margin, left there.

    Every layer is warped over the box it covers only (the plate's pixels elsewhere are
    never touched), which draws the same picture as whole-picture warps at a fraction of
    their cost."""

    width, height = renderer.size
    size = (width, height)
    target = renderer.scene_points(params)
    head_forward = rigid_fit(renderer._reference_ring, head_ring_points(renderer.scene, target))
    head, face, box, labels = _head_masks(renderer, params, target)
    margin = ONLY_MARGIN_SOFT_PX if renderer.soft_outline else ONLY_MARGIN_PX
    clip = None if chroma else _clip_of(only, face, margin)
    out, plate, torso, body_moved = _torso_layer(renderer, body, chroma)
    halo = _warped_mask(renderer.halo_mask, renderer._halo_box, head_forward, size)
    # The mesh's edge and the halo's rigid motion part by a pixel here and there: close the
    # gap (it would show the plate as a dotted seam).
    halo = _close_gap(halo, head)
    person = halo | head
    moved = _head_moved_px(renderer, target)
    if plate is not None:  # the torso's outer edge only: it meets the head inside
        torso = torso & (1 - person)
        strength = min(body_moved / FEATHER_FULL_PX, 1.0)
        _feather(out, plate, torso.view(bool), strength, (torso | person).view(bool), chroma,
                 clip)  # fmt: skip
    # The picture moved with the head, around the head and halo: what their seam fades into.
    around_box = mask_box(person, _BLEED_MARGIN_PX) if moved > 0 else mask_box(halo)
    drawn_box, around = _within(around_box, clip, far_only=True), None
    if drawn_box is not None:
        around = _draw_layer(renderer, out, halo, head_forward, drawn_box, chroma)
    head_box = _within(box, clip)
    if head_box is not None:
        maps = _head_maps(renderer, labels, target, box, head_box)
        _draw_head(renderer, out, _crop(head, head_box).view(bool), maps, head_box, chroma)
    bleed_box = _within(around_box, clip)
    if moved > 0 and around is not None and bleed_box is not None:
        strength = min(moved / FEATHER_FULL_PX, 1.0)
        if bleed_box != drawn_box:  # luma only: the moved picture over the bleed's box
            dx, dy = drawn_box[0], drawn_box[1]
            inner = (bleed_box[0] - dx, bleed_box[1] - dy, bleed_box[2] - dx, bleed_box[3] - dy)
            around = _crop(around, inner)
        _bleed(out, around, bleed_box, person.view(bool), strength, chroma)
    if renderer.soft_outline:
        soften_outline(out, person.view(bool), face, moved, chroma)
    return out, face


def _close_gap(halo: np.ndarray, head: np.ndarray) -> np.ndarray:
    """The halo grown by a pixel into any gap beside the head, off the head's own pixels:
    `cv2.dilate(halo | head) & (1 - head)`, computed over the person's box (and a pixel
    about it) only; zero elsewhere, as there."""
    import cv2

    person = halo | head
    out = np.zeros_like(person)
    box = mask_box(person, 1)
    if box is not None:
        x0, y0, x1, y1 = box
        grown = cv2.dilate(person[y0:y1, x0:x1], _GAP_KERNEL)
        out[y0:y1, x0:x1] = grown & (1 - head[y0:y1, x0:x1])
    return out


def _head_masks(renderer, params: np.ndarray, target: np.ndarray):
    """The head's and the face's masks (H, W uint8, bool), the head's box (None: outside the
    picture) and its triangle labels there."""
    width, height = renderer.size
    scene = renderer.scene
    head = np.zeros((height, width), np.uint8)
    face = np.zeros((height, width), bool)
    box = _box(target[: scene.model.n_vertices + len(scene.outline)], renderer.size)
    labels = None
    if box is not None:
        x0, y0, x1, y1 = box
        labels = _head_labels(renderer, params, target, box)
        head[y0:y1, x0:x1] = labels >= 0
        face[y0:y1, x0:x1] = labels >= renderer._strips
    return head, face, box, labels


def _torso_layer(renderer, body: np.ndarray | None, chroma: bool):
    """The plate with the torso moved by `body` drawn on it (a copy to draw on), the plate
    itself when the torso's edge is to fade into it (None otherwise), the moved torso's mask
    and how far the torso moved. The torso is drawn whole: where the head or its halo covers
    it they are drawn over it, so the picture is the one drawn with the torso cut by them.
    It depends on the reference and `body` only: kept for the next call with the same, and
    drawn whole for that even for a drawing of one box (`compose_layers`' `only`: the next
    frame's set often decodes the same body motion; a whole torso is the same inside any box)."""
    key = (
        renderer.reference_serial,
        None if body is None else np.asarray(body, np.float64).tobytes(),
    )
    kept = getattr(renderer, "_torso_kept", None)
    if kept is not None and kept[0] == key and (kept[1] or not chroma):
        _, _, out, plate, torso, body_moved = kept
        return out.copy(), plate, torso, body_moved
    torso_forward = body_matrix(NO_BODY_MOTION if body is None else body, renderer.anchor)
    out = _plate(renderer, body)
    torso = _warped_mask(renderer._torso_below, renderer._torso_box, torso_forward, renderer.size)
    body_moved = 0.0 if body is None else float(np.hypot(body[0], body[1]) + 100 * abs(body[2]))
    torso_box = mask_box(torso)
    plate = None
    if torso_box is not None:
        plate = out.copy() if body_moved > 0 else None  # the torso's edge fades into it
        _draw_layer(renderer, out, torso, torso_forward, torso_box, chroma)
    renderer._torso_kept = (key, chroma, out, plate, torso, body_moved)
    return out.copy(), plate, torso, body_moved


def _plate(renderer, body: np.ndarray | None) -> np.ndarray:
    """The plate to draw on (a copy), moved by `body`'s camera motion if it has one."""
    import cv2

    plate = renderer.plate_picture()
    if body is None or len(body) < N_BODY or not np.any(body[N_TORSO:]):
        return plate.copy()
    tx, ty = (float(v) for v in body[N_TORSO:])
    return shift_yuv(plate, np.array([[1.0, 0.0, tx], [0.0, 1.0, ty]]), cv2.INTER_LINEAR)


def _bleed(
    out: np.ndarray, around: np.ndarray, box, mask: np.ndarray, strength: float, chroma=True
) -> None:
    """Fade the head's edge outward: the pixels just outside `mask` (the head and its halo)
    in `out` move toward `around` (the picture moved rigidly with the head, over `box`, at
    least `_BLEED_MARGIN_PX` beyond the mask) by up to half, over about `FEATHER_SIGMA_PX`,
    times `strength`; the head's own pixels stay as drawn; the chroma planes too with
    `chroma`."""
    import cv2

    height = mask.shape[0]
    x0, y0, x1, y1 = box
    inside = mask[y0:y1, x0:x1]
    weight = strength * cv2.GaussianBlur(inside.astype(np.float32), (0, 0), FEATHER_SIGMA_PX)
    zero_where(weight, inside)
    if not chroma:
        _blend(out[y0:y1, x0:x1], around[: y1 - y0], weight)
        return
    half = weight[0::2, 0::2]
    box_h = y1 - y0
    planes = out[height:].reshape(2, height // 2, -1)[:, y0 // 2 : y1 // 2, x0 // 2 : x1 // 2]
    toward = around[box_h:].reshape(2, box_h // 2, -1)
    for top, target, w in ((out[y0:y1, x0:x1], around[:box_h], weight),
                           (planes[0], toward[0], half), (planes[1], toward[1], half)):  # fmt: skip
        _blend(top, target, w)


def _blend(top: np.ndarray, toward: np.ndarray, weight: np.ndarray) -> None:
    """`top` (uint8, in place) moved toward `toward` by `weight` (0: unchanged), rounded;
    only the pixels whose weight is not 0 are computed (compiled: `layered_kernels.blend`)."""
    blend(top, toward, weight)


def _head_moved_px(renderer, target: np.ndarray) -> float:
    """How far the head ring moved from the reference (the farthest point, pixels)."""
    ring = head_ring_points(renderer.scene, target)
    return float(np.max(np.hypot(*(ring - renderer._reference_ring).T)))


def _feather(
    out: np.ndarray, under: np.ndarray, mask: np.ndarray, strength: float, solid=None,
    chroma: bool = True, clip=None,
) -> None:  # fmt: skip
    """Fade the pixels of `mask` in `out` into `under` near the edge of `solid` (default
    `mask`) over about `FEATHER_SIGMA_PX`, by `strength` (0: a hard edge, as when the layer has
    not moved); computed over `mask`'s box (and the blur's reach) only, cut to `clip`; the
    chroma planes too with `chroma`."""
    import cv2

    height = mask.shape[0]
    solid = mask if solid is None else solid
    box = _within(mask_box(mask, _BLEED_MARGIN_PX), clip)  # a cut side lies beyond the blur
    if box is None:
        return
    x0, y0, x1, y1 = box
    inner = cv2.GaussianBlur(solid[y0:y1, x0:x1].astype(np.float32), (0, 0), FEATHER_SIGMA_PX)
    # How far each pixel goes toward `under` (1 - the share of itself it keeps).
    away = strength * (1.0 - inner)
    zero_where(away, ~mask[y0:y1, x0:x1])
    half = away[0::2, 0::2]
    rows = slice(y0 // 2, y1 // 2), slice(x0 // 2, x1 // 2)
    top = out[height:].reshape(2, height // 2, -1)
    bottom = under[height:].reshape(2, height // 2, -1)
    _blend(out[y0:y1, x0:x1], under[y0:y1, x0:x1], away)
    for k in range(2 if chroma else 0):
        _blend(top[k][rows], bottom[k][rows], half)
