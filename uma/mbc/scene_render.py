"""The receiver's picture: the whole reference scene warped by the face model, in colour.

Units: pixels; pictures are planar YUV 4:2:0 (H * 3 // 2, W) uint8; parameters as in
`uma.face.geometry`; light as (gain, offset_levels) on the face's luma, faded out just beyond
its edge.

The reference is a full picture the receiver holds together with the pose the model had on it:
by default the description's own picture (its texture where it was cut from, mid-grey around
it), or whatever `set_reference` names later (the last full picture decoded, with the pose the
engine tracked on it). Layered (the default): every reference is cut into a background plate,
a torso moved by the body motion and a head moved by the model (`uma.mbc.layers`, drawn by
`uma.mbc.layered_render`), so the old head is never stretched into the background. Stretched
(`layered=False`, and the talking head's own scene): the scene mesh of `uma.face.scene` (the
face's triangles, a head ring that moves rigidly with the head for hair, ears and neck, and a
far ring fixed well outside the picture) is placed at the reference pose and at the new pose;
each pixel takes the affine map of the triangle drawn there back into the reference, for luma
and chroma alike. Either way the face keeps the reference's colours.
"""

from __future__ import annotations

import numpy as np

from uma.face.describe import ContentDescription
from uma.face.scene import HEAD_RING_SCALE, SceneMesh
from uma.mbc.errors import SceneError
from uma.mbc.layered_kernels import STILL_MAP, relight_face, triangle_maps
from uma.mbc.layered_render import compose_layers, mask_box
from uma.mbc.layers import Plate, body_problem, cut_person, head_ring_points
from uma.mbc.render_memo import RenderMemo
from uma.mbc.scene_reference import description_reference
from uma.mbc.stretched_render import stretched

__all__ = [
    "SceneRenderer",
    "description_reference",
    "LIGHT_GAIN_RANGE",
    "LIGHT_OFFSET_RANGE",
    "HEAD_RING_CHOICES",
]

# The far ring, fixed in the picture, at this many head-ring radii from the face's centre: the
# picture beyond it never moves (a background stays put while a tracked pose jitters). Chosen on
# carphone's and akiyo's frames 150-299 (not the bench's 0-149): against the talking head's
# far ring (1.5 frame diagonals) whole-frame SSIM 0.61 / 0.91 instead of 0.52 / 0.77, face box
# unchanged (+0.1 / +0.2 dB); 2.5 radii gives 0.58 / 0.90.
FAR_RING_HEAD_RADII: float | None = 1.6
HEAD_RING_OUTLINES = 1.4  # the head ring's radius in face-outline radii (hair, ears, neck)
# What `uma.mbc.light.choose_head_ring` picks from: a head ring that carries hair, ears and
# neck with the head (right where the tracked pose is right: the talking head), or one just
# outside the face that lets them follow only in part (better where the pose is off: akiyo's
# bow, carphone's turn; docs/mbc.md).
HEAD_RING_CHOICES = (1.05, HEAD_RING_OUTLINES)
# The halo around the head, in head-ring widths, moved rigidly with the head: hair just outside
# the head ring goes with the person, never into the plate. Chosen on akiyo's and carphone's
# frames 150-299 (face box luma PSNR, quantised; the stretched scene: 22.30 | 21.25 dB): halo
# 0.12 and hair 0.2 gave 21.80 | 19.58, 0.25 and 0.3 21.29 | 19.42, 0.08 and 0.15 22.01 |
# 20.20, 0.05 and 0.1 22.22 | 20.76, 0.02 and 0.05 22.33 | 20.78 (a wider halo carries the
# background around the head with a pose that is off). Then (session mbc3, docs/mbc.md) a thin
# rim and hair carried higher, 0.02 and 0.2: 22.36 | 20.69 against 0.05 and 0.1's 22.23 |
# 20.71, without the hair left above carphone's moved head.
HALO_OF_HEAD = 0.02
# The face's light fades out over this share of the face's width beyond its edge (0: the face
# alone is relit, which left a step where the mesh ends: a seam across carphone's hair).
# Frames 150-299, MBC alone face box dB, akiyo | carphone: 0 22.89 | 21.16, 0.05 22.91 |
# 21.17, 0.1 22.87 | 21.21, 0.2 22.74 | 21.27 (docs/mbc.md, session mbc6).
LIGHT_FEATHER_OF_FACE = 0.05
LIGHT_GAIN_RANGE = (0.25, 4.0)  # a face's luma gain against its reference's
LIGHT_OFFSET_RANGE = (-128.0, 128.0)  # levels


def _front_facing(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    a, b, c = (points[triangles[:, k]] for k in range(3))
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    return cross < 0  # counter-clockwise from the front turns clockwise with y down


class SceneRenderer:
    """Draws the whole scene at given parameters by warping a reference picture (see the module).

    `talking_head_scene` places the rings as `uma.face.scene` does by default (the talking
    head's own scene: its far ring 1.5 frame diagonals away) instead of the receiver's;
    `head_ring_outlines` sizes the receiver's head ring (default `HEAD_RING_OUTLINES`);
    `soften_outline`: soften the drawn outline as the head moves (`uma.mbc.outline`). The
    receiver's settings come from the codec's profile (`uma.mbc.profile`).
    """

    def __init__(
        self,
        description: ContentDescription,
        size: tuple[int, int],
        *,
        talking_head_scene: bool = False,
        head_ring_outlines: float | None = None,
        far_ring_head_radii: float | None = None,
        layered: bool | None = None,
        soften_outline: bool = False,
    ):
        width, height = (int(v) for v in size)
        if width < 2 or height < 2 or width % 2 or height % 2:
            raise SceneError(f"renderer: expected an even picture size, got {width}x{height}")
        ring = HEAD_RING_OUTLINES if head_ring_outlines is None else float(head_ring_outlines)
        if not (np.isfinite(ring) and ring > 1.0):
            raise SceneError(f"head ring: expected more than 1 face-outline radius, got {ring}")
        far = FAR_RING_HEAD_RADII if far_ring_head_radii is None else float(far_ring_head_radii)
        if far is not None and not (np.isfinite(far) and far > 1.0):
            raise SceneError(f"far ring: expected more than 1 head-ring radius, got {far}")
        self.size = (width, height)
        self.description = description
        self.soft_outline = bool(soften_outline)
        self.scene = SceneMesh.build(
            description.model,
            description.params,
            (height, width),
            far_ring_scale=None if talking_head_scene else far,
            head_ring_scale=HEAD_RING_SCALE if talking_head_scene else ring,
        )
        self._strips = len(self.scene.triangles) - len(description.model.triangles)
        self.layered = not talking_head_scene if layered is None else bool(layered)
        self.plate = Plate((width, height)) if self.layered else None
        ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
        self._x, self._y = xs, ys
        self._face_source = None
        self._face_chroma = None
        self._last_face = None
        self._face_read = None  # `face_luma`'s picture and triangle corners, kept
        self._points_kept = None  # `scene_points`: (params' bytes, the scene's points)
        self._memo = RenderMemo()  # cleared by every new reference and face source
        self.luma_only = False  # `set_luma_only`
        self.set_reference(*description_reference(description, self.size))
        # The description's picture is mid-grey around its texture: not background anyone saw.
        # The first real reference replaces that plate instead of being laid over it (the grey
        # would show wherever that reference's person hid the background).
        self._synthetic_plate = True

    def set_reference(
        self,
        picture: np.ndarray,
        params: np.ndarray,
        fresh: np.ndarray | None = None,
        camera: np.ndarray | None = None,
    ) -> None:
        """Render from `picture` (YUV 4:2:0 at the source size) on which the model sits at
        `params` from now on: the model-aided refresh's entry point. `fresh` (H, W bool) says
        which pixels were decoded (the rest drawn by this renderer: the plate learns only
        decoded background; None: all); `camera` (x, y px) the camera's motion from the old
        reference to `picture` (the plate moves by it first; None: none). A picture of
        another size or a pose no face has is a `SceneError`; the old reference stays."""
        width, height = self.size
        picture = np.asarray(picture)
        if picture.shape != (height * 3 // 2, width) or picture.dtype != np.uint8:
            raise SceneError(
                f"reference: expected a {width}x{height} YUV 4:2:0 uint8 picture, got "
                f"{picture.shape} {picture.dtype}"
            )
        params = np.asarray(params, dtype=np.float64)
        expected = (6 + self.description.model.n_actions,)
        if params.shape != expected or not np.all(np.isfinite(params)) or not params[2] > 0:
            raise SceneError(
                f"reference pose: expected {expected[0]} finite parameters with a positive "
                f"scale, got {np.array2string(params, precision=3, threshold=8)}"
            )
        self._memo.clear()
        self._face_read = None
        self.reference = np.ascontiguousarray(picture)
        self.reference_params = params.copy()
        self.reference_serial = getattr(self, "reference_serial", 0) + 1  # one per reference
        self._reference_points = self.scene.points(params)
        if self.layered:
            if getattr(self, "_synthetic_plate", False):
                self.plate.forget()
            self._synthetic_plate = False
            if camera is not None:
                self.plate.shift(camera)
            self._cut_layers(params, fresh)
        chroma = self.reference[height:].reshape(2, height // 2, width // 2)
        self._u, self._v = np.ascontiguousarray(chroma[0]), np.ascontiguousarray(chroma[1])

    def set_face_source(self, use_description: bool) -> None:
        """Draw the face's own triangles from the description's picture (its pose there is
        known exactly) and only the rest of the scene from the reference: for a reference whose
        pose is only approximately known (the receiver's last picture, shown a while before the
        stream's first pose)."""
        self._face_source = self._face_read = None
        self._memo.clear()
        if use_description:
            self._face_source = description_reference(self.description, self.size)

    def set_luma_only(self, luma_only: bool = True) -> None:
        """Draw luma only from now on (an engine's mirror: everything it decides reads luma);
        every picture's luma is the one a full renderer draws, its chroma left undrawn, and
        its plate learns no chroma. Set before the first `set_reference` that matters."""
        self.luma_only = bool(luma_only)
        self._memo.clear()
        if self.plate is not None:
            self.plate.luma_only = self.luma_only

    def scene_points(self, params: np.ndarray) -> np.ndarray:
        """`self.scene.points(params)`, kept for the last `params` asked (the layered drawing's
        and the face paste's of one frame: the model projected once); never written to."""
        key = np.asarray(params, dtype=np.float64).tobytes()
        kept = self._points_kept
        if kept is None or kept[0] != key:
            kept = self._points_kept = (key, self.scene.points(params))
        return kept[1]

    def kept_points(self, params: np.ndarray) -> np.ndarray | None:
        """The scene's points at `params` when `scene_points` has them, else None."""
        kept = self._points_kept
        key = np.asarray(params, dtype=np.float64).tobytes()
        return kept[1] if kept is not None and kept[0] == key else None

    def _drawn(self, target: np.ndarray) -> np.ndarray:
        """Triangles to draw: the face's front-facing ones and every background strip (a strip
        folded over by a large move still covers its pixels; left out, they would show the
        reference's old head there)."""
        drawn = _front_facing(target, self.scene.triangles)
        drawn[: self._strips] = True
        if self.layered:  # the head alone: face and head ring, no strips out to the far ring
            drawn[self._strips // 2 : self._strips] = False
        return drawn

    def maps(self, params: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The stretched scene's (not layered): where each pixel reads the reference at
        `params`: map_x, map_y (H, W) float32, and the mask of the face's own pixels."""
        from uma.face.render import barycentric_affine, triangle_labels

        scene = self.scene
        width, height = self.size
        target = scene.points(params)
        labels = triangle_labels(
            target,
            scene.triangles,
            (height, width),
            triangle_mask=self._drawn(target),
            depth=scene.depth(params),
        )
        affine = barycentric_affine(target, scene.triangles)
        coeffs = np.einsum("tjk,tjc->tck", affine, self._reference_points[scene.triangles])
        # A pixel no triangle covers reads the picture where it is.
        map_x, map_y = triangle_maps(labels, coeffs, STILL_MAP, self._x, self._y)
        return map_x, map_y, labels >= self._strips

    def face_luma(self, params: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple[int, int]]:
        """The face's own luma at `params` without light, over its bounding box only: (patch,
        mask, (x0, y0) of the box); what the encoder measures light against, at a fraction of
        `render`'s cost (`uma.mbc.face_patch`). Empty when the face lies outside the picture."""
        from uma.face.geometry import project
        from uma.mbc.face_patch import face_corners, face_luma

        model = self.description.model
        kept = self.kept_points(params)  # the layered drawing's of this frame, if any
        target = project(model, params) if kept is None else kept[: model.n_vertices]
        if self._face_read is None:  # where the face reads from: new with each reference
            picture, source = self.reference, self._reference_points[: model.n_vertices]
            if self._face_source is not None:
                picture, source = self._face_source[0], project(model, self._face_source[1])
            self._face_read = (picture, face_corners(model, source))
        patch, mask, origin, maps = face_luma(
            model, self.size, target, *self._face_read, (self._x, self._y)
        )
        if maps is not None:
            self._last_face = maps
        return patch, mask, origin

    def render(
        self,
        params: np.ndarray,
        light: tuple[float, float] | None = None,
        body: np.ndarray | None = None,
        *,
        luma_only: bool = False,
        only=None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """The picture (YUV 4:2:0) at `params` and the mask of the face's pixels; `light`
        (gain, offset in levels) relights the face's luma against the reference's; `body`
        (layered only) moves the torso (`uma.mbc.layers.BODY_NAMES`; None: still);
        `luma_only`: the same luma, the chroma planes left undrawn (a judge's); with it,
        `only`: a function of the face's mask giving the box (x0, y0, x1, y1) the caller
        reads, the luma the same there and the rest of the picture left as drawing that box
        left it (`uma.mbc.layered_render.compose_layers`; never kept for another call). Light out
        of `LIGHT_GAIN_RANGE`/`LIGHT_OFFSET_RANGE`, an absurd body motion or values not
        finite are a `SceneError` (nothing drawn: the caller keeps its last picture)."""

        params = self._checked(params, body)
        width, height = self.size
        luma_only = luma_only or self.luma_only  # a luma-only renderer's memo holds luma only
        memo = not luma_only or self.luma_only
        kept = self._memo.get(params, light, body) if memo else None
        if kept is not None:
            return kept
        memo = memo and (only is None or not luma_only)
        if self.layered:
            only = only if luma_only else None
            out, face = compose_layers(self, params, body, chroma=not luma_only, only=only)
        else:
            map_x, map_y, face = self.maps(params)
            out = stretched(self.reference, (self._u, self._v), map_x, map_y)
        luma = out[:height]
        if self._face_source is not None:
            self._paste_face(
                luma, params, luma_only
            )  # before the light: the pasted face is relit too
        if light is not None:
            relight_face(luma, face, _checked_light(light), LIGHT_FEATHER_OF_FACE)
        chroma = out[height:].reshape(2, height // 2, width // 2)
        if self._face_source is not None and self._face_chroma is not None and not luma_only:
            (x0, y0), mask, planes = self._face_chroma
            for plane, patch in zip(chroma, planes, strict=True):
                h, w = patch.shape
                box = plane[y0 : y0 + h, x0 : x0 + w]
                box[mask] = patch[mask]
        if memo:
            self._memo.put(params, light, body, out, face)
        return out, face

    def face_mask(self, params: np.ndarray, light=None, body=None) -> np.ndarray:
        """The face's pixels (H, W bool) `render` returns at these inputs, nothing drawn."""
        from uma.mbc.layered_render import face_mask

        return face_mask(self, self._checked(params, body, light))

    def _checked(self, params, body, light=None) -> np.ndarray:
        """`params` as float64, or `render`'s `SceneError` for inputs it cannot draw."""
        params = np.asarray(params, dtype=np.float64)
        if not np.all(np.isfinite(params)) or not params[2] > 0:
            raise SceneError(f"parameters: expected finite with a positive scale, got {params}")
        if body is not None and (problem := body_problem(body, self.size)):
            raise SceneError(problem)
        if light is not None:
            _checked_light(light)
        return params

    def _cut_layers(self, params: np.ndarray, fresh: np.ndarray | None) -> None:
        """The reference cut at `params` (`uma.mbc.layers.cut_person`), the plate taught the
        rest."""
        head, self.halo_mask, self.torso_mask, self.anchor = cut_person(
            self.scene, self._reference_points, self.size, HALO_OF_HEAD
        )
        self._reference_ring = head_ring_points(self.scene, self._reference_points)
        below = np.repeat(self.torso_mask[-1:], self.size[1] // 2, axis=0)
        self._torso_below = np.ascontiguousarray(np.vstack([self.torso_mask, below]))
        # The boxes the masks' pixels lie in: each frame warps only the box they move to.
        self._torso_box = mask_box(self._torso_below)
        self._halo_box = mask_box(self.halo_mask)
        person = (head | self.halo_mask | self.torso_mask) > 0
        self.person_mask = person
        self.plate.update(self.reference, person, fresh)

    def plate_picture(self) -> np.ndarray | None:
        """The plate to show behind the person; the reference itself once the plate is lost
        (its reason stays in `plate.reason`)."""
        if self.plate is None:
            return None
        return self.plate.picture if self.plate.known.any() else self.reference

    def _paste_face(self, luma: np.ndarray, params: np.ndarray, luma_only=False) -> None:
        """The face's pixels from the description's picture into `luma`; its chroma kept for
        `render` to paste after the scene's chroma (a face box at an odd corner keeps the
        scene's chroma that frame), not drawn for a `luma_only` picture."""
        import cv2

        width, height = self.size
        self._face_chroma = None
        patch, mask, (x0, y0) = self.face_luma(params)
        h, w = patch.shape
        if h == 0 or w == 0:
            return
        box = luma[y0 : y0 + h, x0 : x0 + w]
        box[mask] = patch[mask]
        if x0 % 2 or y0 % 2 or h < 2 or w < 2 or luma_only:
            return
        map_x, map_y, picture = self._last_face
        h2, w2 = h // 2 * 2, w // 2 * 2
        cx = (map_x[0:h2:2, 0:w2:2] + map_x[1:h2:2, 1:w2:2] - 1.0) * 0.25
        cy = (map_y[0:h2:2, 0:w2:2] + map_y[1:h2:2, 1:w2:2] - 1.0) * 0.25
        planes = picture[height:].reshape(2, height // 2, width // 2)
        chroma = [
            cv2.remap(np.ascontiguousarray(plane), cx, cy, cv2.INTER_LINEAR,
                      borderMode=cv2.BORDER_REPLICATE)
            for plane in planes
        ]  # fmt: skip
        self._face_chroma = ((x0 // 2, y0 // 2), mask[0:h2:2, 0:w2:2], chroma)


def _checked_light(light) -> tuple[float, float]:
    gain, offset = (float(v) for v in light)
    low, high = LIGHT_GAIN_RANGE
    if not (np.isfinite(gain) and low <= gain <= high):
        raise SceneError(f"light gain: expected in [{low}, {high}], got {gain}")
    low, high = LIGHT_OFFSET_RANGE
    if not (np.isfinite(offset) and low <= offset <= high):
        raise SceneError(f"light offset: expected in [{low}, {high}] levels, got {offset}")
    return gain, offset
