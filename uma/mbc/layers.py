"""The receiver's layered scene: a background plate, a torso moved by the body motion, a head.

Units: pixels (x right, y down); pictures planar YUV 4:2:0 (H * 3 // 2, W) uint8; body motion
as `BODY_NAMES` (a 2-D similarity about the torso's anchor, the reference's chin).

One stretched picture drags the old head's pixels into the background when the head moves
(the "second head" beside the new one). Here the reference is cut into layers instead:

- the **person**: the head (the face and the head ring, as `uma.face.scene` places them at the
  reference pose) and below it the torso (a generous head-and-shoulders outline from the chin
  to the picture's bottom edge, `torso_polygon`);
- the **plate**: every pixel known to lie outside the person, from the reference and from
  every later reference (a refresh); what was never seen (behind the person) is filled from
  its surroundings (`fill_unknown`, a push-pull pyramid), so an uncovered spot shows plausible
  background, never the old head.

`uma.mbc.scene_render.SceneRenderer` draws the plate, then the torso moved by the body motion,
then the head moved by its pose.
"""

from __future__ import annotations

import numpy as np

from uma.mbc.band_parts import inpaint_band
from uma.mbc.errors import SceneError
from uma.mbc.fill_kernels import pull_level, settle

__all__ = [
    "BODY_NAMES",
    "CAMERA_NAMES",
    "NO_BODY_MOTION",
    "N_BODY",
    "N_TORSO",
    "Plate",
    "body_matrix",
    "body_problem",
    "cut_person",
    "head_ring_points",
    "rigid_fit",
    "invert_affine",
    "fill_unknown",
    "fill_unknown_planes",
    "shift_yuv",
    "torso_polygon",
]

# A 2-D rigid motion of the torso about its anchor: shift x and y (px), rotation (rad). (A
# scale was tried: ECC traded it against the shift on carphone, shrinking the torso by 17 %.)
# Then the camera's motion: the background's shift (px) from the reference to the frame, which
# moves the plate (a hand-held camera moves the whole scene; the torso's motion includes it).
TORSO_NAMES = ("body_tx_px", "body_ty_px", "body_rotation_rad")
CAMERA_NAMES = ("camera_tx_px", "camera_ty_px")
BODY_NAMES = TORSO_NAMES + CAMERA_NAMES
N_TORSO = len(TORSO_NAMES)
N_BODY = len(BODY_NAMES)
NO_BODY_MOTION = np.zeros(N_BODY)
# What a body can do between a reference and a frame; beyond is absurd (a typed error).
BODY_SHIFT_MAX_OF_SIZE = 0.5  # of the picture's width or height
BODY_ROTATION_MAX_RAD = 0.5
# A new reference whose known background departs from the plate's by more than this median
# (luma levels) is another scene (a cut, a moved camera): the plate starts again from it.
PLATE_MISMATCH_LEVELS = 40.0
EDGE_BAND_PX = 3  # the unknown band along the known background that is inpainted, not averaged
# How that band is filled, luma and chroma: the "nearest" known pixel, or OpenCV's "telea"
# inpainting (docs/mbc.md, session mbc4). Nearest on luma too: a new reference 35-45 % less CPU
# at CIF, frames 150-299 within 0.03 dB, but foreman -0.16 to -0.19 dB with the refresh; on
# chroma alone: 19-24 % less CPU, luma figures identical.
EDGE_FILL = "telea"
EDGE_FILL_CHROMA = "nearest"
# Telea's radius over that band: what a band pixel reads of its neighbours (its cost per band
# pixel grows with its square); 1 px on pictures CIF wide or wider (2 saved a CIF luma fill
# 0.45 ms against 3, session mbc20; 1 a further share, every clip's face within 0.01 dB,
# branch mbc23); QCIF keeps 3 (foreman lost 0.03 dB at 2; docs/mbc.md).
EDGE_RADIUS_PX = 3
EDGE_RADIUS_CIF_PX = 1
CIF_WIDTH_PX = 352
HAIR_OF_HEAD = 0.2  # how far above the head ring the halo reaches, in head-ring heights
_PLATE_MIN_OVERLAP = 0.05  # of the picture, to judge a mismatch at all


def shift_yuv(picture: np.ndarray, matrix: np.ndarray, flags: int) -> np.ndarray:
    """A YUV 4:2:0 `picture` moved by the 2x3 forward map `matrix` (luma pixels), its edges
    replicated into what the move uncovers."""
    import cv2

    height, width = picture.shape[0] * 2 // 3, picture.shape[1]
    out = np.empty_like(picture)
    edge = cv2.BORDER_REPLICATE
    out[:height] = cv2.warpAffine(picture[:height], matrix, (width, height), flags=flags,
                                  borderMode=edge)  # fmt: skip
    half = matrix.astype(np.float64).copy()
    half[:, 2] = (matrix[:, :2] @ (0.5, 0.5) + matrix[:, 2] - 0.5) / 2.0
    chroma = picture[height:].reshape(2, height // 2, width // 2)
    moved = out[height:].reshape(2, height // 2, width // 2)
    for k in range(2):
        moved[k] = cv2.warpAffine(np.ascontiguousarray(chroma[k]), half,
                                  (width // 2, height // 2), flags=flags, borderMode=edge)  # fmt: skip
    return out


def body_problem(body, size: tuple[int, int]) -> str:
    """Why `body` (`BODY_NAMES`) is absurd on a picture of `size` (W, H), or ""."""
    body = np.asarray(body, dtype=np.float64)
    if body.shape not in ((N_TORSO,), (N_BODY,)) or not np.all(np.isfinite(body)):
        return (
            f"body motion: expected {N_TORSO} or {N_BODY} finite values {BODY_NAMES}, got {body!r}"
        )
    width, height = size
    tx, ty, rotation = body[:N_TORSO]
    shifts = [("body motion", tx, ty)]
    if body.size == N_BODY:
        shifts.append(("camera motion", body[N_TORSO], body[N_TORSO + 1]))
    for name, x, y in shifts:
        if abs(x) > BODY_SHIFT_MAX_OF_SIZE * width or abs(y) > BODY_SHIFT_MAX_OF_SIZE * height:
            return f"{name}: shift ({x:.1f}, {y:.1f}) px beyond half the {width}x{height} picture"
    if abs(rotation) > BODY_ROTATION_MAX_RAD:
        return f"body motion: rotation {rotation:.3f} rad beyond +-{BODY_ROTATION_MAX_RAD}"
    return ""


def body_matrix(body, anchor: np.ndarray) -> np.ndarray:
    """The 2x3 forward map (reference pixel to frame pixel) of `body`'s torso motion about
    `anchor` (x, y)."""
    tx, ty, rotation = (float(v) for v in body[:N_TORSO])
    c, n = np.cos(rotation), np.sin(rotation)
    ax, ay = float(anchor[0]), float(anchor[1])
    return np.array([[c, -n, ax + tx - c * ax + n * ay], [n, c, ay + ty - n * ax - c * ay]])


def rigid_of(affine: np.ndarray, anchor: np.ndarray) -> np.ndarray:
    """The body motion (`BODY_NAMES`) of a 2x3 forward rigid map `affine`, about `anchor`."""
    rotation = float(np.arctan2(affine[1, 0] - affine[0, 1], affine[0, 0] + affine[1, 1]))
    moved = affine[:, :2] @ anchor + affine[:, 2]
    tx, ty = moved - anchor
    return np.array([tx, ty, rotation])


def torso_polygon(head_points: np.ndarray, chin: np.ndarray, height: int) -> np.ndarray:
    """A generous head-and-shoulders outline (int32 polygon) below the head whose projected
    head-ring points are `head_points`: a neck as wide as the head ring's lower half at `chin`,
    shoulders 1.25 head-ring widths out on either side, down past the picture's bottom."""
    x0, x1 = float(head_points[:, 0].min()), float(head_points[:, 0].max())
    width = max(x1 - x0, 1.0)
    centre = (x0 + x1) / 2.0
    cy = float(chin[1])
    bottom = max(height, cy + width) + 2.0
    shoulder_y = cy + 0.45 * width
    half_neck, half_shoulder = 0.42 * width, 1.25 * width
    points = [
        (centre - half_neck, cy - 0.15 * width),
        (centre - half_shoulder, shoulder_y),
        (centre - 1.4 * width, bottom),
        (centre + 1.4 * width, bottom),
        (centre + half_shoulder, shoulder_y),
        (centre + half_neck, cy - 0.15 * width),
    ]
    return np.rint(points).astype(np.int32)


def cut_person(scene, points: np.ndarray, size: tuple[int, int], halo_of_head: float):
    """The person on a reference whose scene points (`uma.face.scene.SceneMesh.points`) are
    `points`, in a picture of `size` (W, H), as uint8 0/1 masks: the head (face and head
    ring), its halo (`halo_of_head` head-ring widths around it: hair just outside the ring,
    moved rigidly with the head) and the torso (the torso outline less head and halo); and the
    torso's anchor (the chin, x and y)."""
    import cv2

    from uma.face.render import triangle_labels

    width, height = size
    strips = len(scene.triangles) - len(scene.model.triangles)
    drawn = np.ones(len(scene.triangles), bool)
    drawn[strips // 2 : strips] = False  # the head alone: no strips out to the far ring
    labels = triangle_labels(points, scene.triangles, (height, width), triangle_mask=drawn)
    head = (labels >= 0).astype(np.uint8)
    ring = head_ring_points(scene, points)
    rim = points[scene.outline]
    anchor = rim[int(np.argmax(rim[:, 1]))].astype(np.float64)
    torso = np.zeros((height, width), np.uint8)
    cv2.fillPoly(torso, [torso_polygon(ring, anchor, height)], 1)
    radius = max(3, int(round(halo_of_head * np.ptp(ring[:, 0]))))
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1))
    # Hair rises above the face's outline: the halo reaches `HAIR_OF_HEAD` of the head higher.
    rise = int(round(HAIR_OF_HEAD * np.ptp(ring[:, 1])))
    raised = head.copy()
    if 0 < rise < height:
        raised[:-rise] |= head[rise:]
    halo = cv2.dilate(raised, kernel) & (1 - head)
    torso &= 1 - (head | halo)
    return head, halo, torso, anchor


def head_ring_points(scene, points: np.ndarray) -> np.ndarray:
    """The head ring's projected points among a scene's `points`."""
    n, m = scene.model.n_vertices, len(scene.outline)
    return points[n : n + m]


def invert_affine(matrix: np.ndarray) -> np.ndarray:
    """The inverse of a 2x3 affine map."""
    import cv2

    return cv2.invertAffineTransform(matrix)


def rigid_fit(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The 2x3 similarity (rotation, scale, shift) that best maps `source` points onto
    `target` points (least squares)."""
    ms, mt = source.mean(axis=0), target.mean(axis=0)
    a, b = source - ms, target - mt
    denominator = float((a**2).sum())
    if denominator <= 1e-9:
        return np.array([[1.0, 0.0, mt[0] - ms[0]], [0.0, 1.0, mt[1] - ms[1]]])
    c = float((a * b).sum()) / denominator
    n = float((a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum()) / denominator
    linear = np.array([[c, -n], [n, c]])
    return np.column_stack([linear, mt - linear @ ms])


def fill_unknown(plane: np.ndarray, known: np.ndarray, edge: str | None = None) -> np.ndarray:
    """`plane` (H, W) with the pixels not `known` filled smoothly from the known ones (a
    push-pull pyramid: averages of the known pixels at ever coarser levels, pulled back
    down), the band next to the known pixels by `edge` (`_continue_edges`; None:
    `EDGE_FILL`). Known pixels are kept exactly; with none known, mid-grey."""
    return fill_unknown_planes((plane,), known, edge)[0]


def fill_unknown_planes(planes, known: np.ndarray, edge: str | None = None) -> list[np.ndarray]:
    """Each of `planes` ((H, W) each) as `fill_unknown` fills it over the one mask `known`;
    what depends on the mask alone (the weights' pyramid, the band and, for "nearest", each
    band pixel's nearest known one) is computed once for all."""
    import cv2

    if not known.any():
        return [np.full_like(plane, 128) for plane in planes]
    weights = [known.astype(np.float32)]
    while min(weights[-1].shape) > 2:
        w = weights[-1]
        size = (max(w.shape[1] // 2, 1), max(w.shape[0] // 2, 1))
        weights.append(cv2.resize(w, size, interpolation=cv2.INTER_AREA))
    edge = EDGE_FILL if edge is None else edge
    band = _edge_band(known, edge)
    return [_continue_edges(_push_pull(plane, known, weights), known, edge, band=band)
            for plane in planes]  # fmt: skip


def _push_pull(plane: np.ndarray, known: np.ndarray, weights: list[np.ndarray]) -> np.ndarray:
    """`plane` where `known`, elsewhere its known pixels' averages at ever coarser levels
    (`weights`: the known mask's pyramid, float32) pulled back down, rounded to uint8."""
    import cv2

    values = plane.astype(np.float32) * weights[0]
    levels = [values]
    for w in weights[1:]:
        levels.append(cv2.resize(levels[-1], (w.shape[1], w.shape[0]),
                                 interpolation=cv2.INTER_AREA))  # fmt: skip
    v, w = levels[-1], weights[-1]
    filled = np.where(w > 1e-6, v / np.maximum(w, 1e-6), float(values.sum() / weights[0].sum()))
    for v, w in zip(reversed(levels[:-1]), reversed(weights[:-1]), strict=True):
        filled = cv2.resize(filled, (v.shape[1], v.shape[0]), interpolation=cv2.INTER_LINEAR)
        if v is values:  # the finest level, w 0 or 1: its pull is `filled` where not known
            break
        up, filled = filled, np.empty_like(v)  # t (v / max(w, 1e-6)) + (1 - t) up, t = clip(w)
        pull_level(v, w, up, np.float32(1e-6), filled)
    out = np.empty_like(plane)  # plane where known, else rint(filled) clipped to 0-255
    settle(np.ascontiguousarray(plane), known, filled, out)
    return out


def _edge_band(known: np.ndarray, edge: str, band_px: int = EDGE_BAND_PX):
    """The unknown pixels within `band_px` of a known one (uint8 0/1) and, for `edge`
    "nearest", every pixel's nearest known one (labels numbering the known pixels in raster
    order from 1; an exact Euclidean distance transform), else None."""
    import cv2

    kernel = np.ones((2 * band_px + 1, 2 * band_px + 1), np.uint8)
    near = cv2.dilate(known.view(np.uint8), kernel) & ~known.view(np.uint8) & 1
    labels = None
    if edge == "nearest" and near.any():
        _, labels = cv2.distanceTransformWithLabels(
            (~known).view(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE,
            labelType=cv2.DIST_LABEL_PIXEL,
        )  # fmt: skip
    return near, labels


def _continue_edges(filled: np.ndarray, known: np.ndarray, edge: str, band_px: int = EDGE_BAND_PX,
                    band=None):  # fmt: skip
    """`filled` (uint8, the push-pull fill) with the unknown pixels within `band_px` of a known
    one taken instead from the known background: its nearest known pixel (`edge`
    "nearest") or OpenCV's Telea inpainting from the known pixels and the fill beyond
    ("telea", radius `EDGE_RADIUS_CIF_PX` from CIF's width up, else `EDGE_RADIUS_PX`); `band`: `_edge_band`'s for this mask (None: found here). Either way edges and
    gradients of the background continue into the band: a person moved by a pixel uncovers
    it, and the smooth fill alone, an average of what lies on both sides of an edge, showed
    there as a dotted line along the person's outline."""
    near, labels = _edge_band(known, edge, band_px) if band is None else band
    if filled.dtype != np.uint8 or not near.any():
        return filled
    where = near.view(bool)
    if edge == "nearest":
        out = filled.copy()
        out[where] = filled[known][labels[where] - 1]
        return out
    radius_px = EDGE_RADIUS_CIF_PX if filled.shape[1] >= CIF_WIDTH_PX else EDGE_RADIUS_PX
    # Telea, part by part; it writes only the band's pixels (the rest is `filled`'s copy)
    return inpaint_band(filled, near, radius_px)


class Plate:
    """The background the receiver knows: a YUV 4:2:0 picture, the mask of its pixels seen
    outside the person, and the same picture with the rest filled (`picture`). A `luma_only`
    plate (an engine's mirror, which reads luma only) learns and fills no chroma: its chroma
    planes stay mid-grey, its luma is the same as a full plate's."""

    def __init__(self, size: tuple[int, int]) -> None:
        width, height = size
        self.size = (width, height)
        self.known = np.zeros((height, width), bool)
        self.seen = np.full((height * 3 // 2, width), 128, np.uint8)
        self.picture = self.seen.copy()
        self.reason = "no plate yet"
        self.luma_only = False

    def update(
        self, picture: np.ndarray, person: np.ndarray, fresh: np.ndarray | None = None
    ) -> str:
        """Learn the pixels of `picture` outside `person` (H, W bool), newest first, of those
        `fresh` (H, W bool: decoded, not drawn by the receiver; None: all); "" or why the plate
        started again (the new picture's background does not match the plate's)."""
        width, height = self.size
        if picture.shape != self.seen.shape or person.shape != (height, width):
            raise SceneError(
                f"plate: expected a {width}x{height} picture and person mask, got "
                f"{picture.shape} and {person.shape}"
            )
        # Not decoded (drawn by the receiver itself): taught only where nothing better is known
        # (the torso it drew there beats a fill, which showed as dark bands where the person
        # had stood on an earlier reference).
        outside = ~person if fresh is None else ~person & (fresh | ~self.known)
        reason = ""
        both = outside & self.known
        if np.count_nonzero(both) / both.size > _PLATE_MIN_OVERLAP:  # both.mean(), to the bit
            luma = picture[:height]
            diff = np.abs(luma[both].astype(np.int16) - self.seen[:height][both].astype(np.int16))
            if float(np.median(diff)) > PLATE_MISMATCH_LEVELS:
                reason = (
                    f"plate: the new reference's background departs from the plate by a median "
                    f"{float(np.median(diff)):.0f} levels (> {PLATE_MISMATCH_LEVELS:.0f}): started again"
                )
                self.known[:] = False
        np.copyto(self.seen[:height], picture[:height], where=outside)
        chroma_out = outside[0::2, 0::2] & outside[1::2, 1::2]
        self.known |= outside
        known_chroma = self.known[0::2, 0::2] & self.known[1::2, 1::2]
        seen = self.seen[height:].reshape(2, height // 2, width // 2)
        new = picture[height:].reshape(2, height // 2, width // 2)
        self.picture = np.empty_like(self.seen)
        self.picture[:height] = fill_unknown(self.seen[:height], self.known)
        filled = self.picture[height:].reshape(2, height // 2, width // 2)
        if self.luma_only:
            filled[:] = 128
        else:  # both chroma planes over one mask: its band found once
            for k in range(2):
                np.copyto(seen[k], new[k], where=chroma_out)
            filled[:] = fill_unknown_planes(seen, known_chroma, EDGE_FILL_CHROMA)
        self.reason = reason
        return reason

    def shift(self, camera) -> None:
        """Move what the plate knows by the camera's shift `camera` (x, y px, reference to
        the new reference's frame): a new reference then meets its background where it is."""
        import cv2

        tx, ty = (float(v) for v in camera)
        if tx == 0.0 and ty == 0.0:
            return
        width, height = self.size
        matrix = np.array([[1.0, 0.0, tx], [0.0, 1.0, ty]])
        self.seen = shift_yuv(self.seen, matrix, cv2.INTER_LINEAR)
        self.picture = shift_yuv(self.picture, matrix, cv2.INTER_LINEAR)
        known = cv2.warpAffine(self.known.view(np.uint8), matrix, (width, height),
                               flags=cv2.INTER_NEAREST, borderValue=0)  # fmt: skip
        self.known = known.view(bool)

    def forget(self) -> None:
        """The plate is lost: nothing known (the renderer falls back to its reference)."""
        self.known[:] = False
        self.reason = "plate lost"
