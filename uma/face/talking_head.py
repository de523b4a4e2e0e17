"""A talking-head source with exact ground truth: a real face photograph animated by the model.

Units: pixels, radians, seconds; frames are planar YUV 4:2:0 (H * 3 // 2, W) uint8.

The default face is scikit-image's astronaut photograph (public domain) with the hand-clicked
feature points of `codecs/face/astronaut.yaml`. The head turns, nods and tilts, drifts and
breathes in scale; the jaw and lips move in a speech-like rhythm (syllables at ~4 Hz in
phrases with pauses); the eyes blink every few seconds; the light changes in overall gain and in
direction (a key light swinging around the camera's axis shades the face through the model's
normals, Lambert's law with some ambient light, relative to the photograph's own frontal light);
the sensor adds Gaussian noise. The whole frame is one mesh (`uma.face.scene`): hair, ears and
neck follow the head, the background stays, and no seam shows where the face meets them.
All motion is deterministic from the seed. `ground_truth(i)` gives the parameters, projected
model points and light of frame i, exactly those used to render it.

Driven by an MPEG-4 `.fap` file instead (`fap=`, `uma source synth --fap FILE`), frame i takes
the file's frame i: head rotation from FAPs 48-50 and action units from the low-level FAPs
(`uma.face.fap`, `uma.face.fap_map`), added to the template's own pose and expression, which are MPEG-4's neutral
face here. Everything the file does not say is held still: no drift in position or scale, no
speech or blinks of our own, the template's light (gain 1, frontal); sensor noise stays.
Past the file's last frame the last one holds.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from uma.face.describe import ContentDescription, read_points
from uma.face.fap import FapSequence
from uma.face.fap_map import fap_units, faps_to_parameters
from uma.face.geometry import N_POSE, project
from uma.face.render import barycentric_affine, triangle_labels
from uma.face.scene import SceneMesh

__all__ = ["TalkingHeadSource", "Motion", "astronaut_description", "astronaut_scene"]

AMBIENT = 0.4  # share of the light that does not depend on the surface's direction


@dataclass(frozen=True)
class Motion:
    """Amplitudes of the animation; zero any of them for a simpler clip."""

    yaw_rad: float = 0.18
    pitch_rad: float = 0.10
    roll_rad: float = 0.06
    shift_frac: float = 0.03  # of the frame width
    scale_frac: float = 0.04
    speech: float = 1.0
    blinks: bool = True
    light_gain: float = 0.15  # relative swing of the overall brightness
    light_angle_rad: float = 0.5  # how far the key light swings away from the camera's axis
    noise_std: float = 2.0  # grey levels

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not isinstance(value, bool) and not (np.isfinite(value) and value >= 0):
                raise ValueError(f"Motion.{name}: expected a finite number >= 0, got {value!r}")
        if self.light_gain >= 1:
            raise ValueError(f"Motion.light_gain: expected below 1, got {self.light_gain}")


CANVAS_MARGIN_FRAC = 0.2  # of the frame height, photograph kept around the frame on every side


def astronaut_description(width: int, height: int) -> ContentDescription:
    """The astronaut, cropped around her face to `width`:`height` and described from its points."""
    return astronaut_scene(width, height)[0]


def astronaut_scene(width: int, height: int) -> tuple[ContentDescription, np.ndarray, int]:
    """The astronaut's description (texture = the frame), and the photograph around the frame:
    a canvas with `margin` pixels more on every side, so a head moving toward the frame's edge
    brings in real picture rather than a repeated border."""
    import cv2
    import skimage.data

    from uma.paths import codecs_dir

    image = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    points = read_points(codecs_dir() / "face" / "astronaut.yaml")
    xy = np.array(list(points.values()))
    centre = xy.mean(axis=0)
    face_h = xy[:, 1].max() - xy[:, 1].min()
    crop_h = face_h / 0.42  # the clicked points span ~42 % of the frame height
    crop_w = crop_h * width / height
    x0, y0 = centre[0] - crop_w / 2, centre[1] - crop_h / 2 + 0.06 * crop_h
    scale = height / crop_h
    margin = int(round(CANVAS_MARGIN_FRAC * height))
    warp = np.float32([[scale, 0, margin - x0 * scale], [0, scale, margin - y0 * scale]])
    canvas = cv2.warpAffine(
        image,
        warp,
        (width + 2 * margin, height + 2 * margin),
        flags=cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_REFLECT,
    )
    frame = np.ascontiguousarray(canvas[margin : margin + height, margin : margin + width])
    moved = {k: ((x - x0) * scale, (y - y0) * scale) for k, (x, y) in points.items()}
    # The whole frame is the texture: the talking head renders over it.
    return describe_full(frame, moved), canvas, margin


def describe_full(frame: np.ndarray, points) -> ContentDescription:
    """Like `describe`, but the texture is the whole frame (no crop)."""
    from uma.face.fit_points import fit_points
    from uma.face.load import load_model

    model = load_model()
    fit = fit_points(model, points, image_shape=frame.shape[:2])
    if not fit:
        raise RuntimeError(f"cannot fit the source's points: {fit.reason}")
    return ContentDescription(
        model=model.personalised(fit.shape),
        texture=frame,
        params=fit.params,
        shape=fit.shape,
        points=dict(points),
        fit_rms_px=fit.rms_px,
    )


class TalkingHeadSource:
    """Frames of an animated face with per-frame ground truth; deterministic from `seed`."""

    def __init__(
        self,
        width: int = 352,
        height: int = 288,
        fps: float = 25.0,
        *,
        seed: int = 0,
        motion: Motion | None = None,
        description: ContentDescription | None = None,
        frame_count: int | None = None,
        fap: FapSequence | None = None,
    ) -> None:
        self.width, self.height, self.fps = width, height, float(fps)
        self.name = "talking-head"
        self.frame_count = frame_count
        self.seed = seed
        self.motion = motion or Motion()
        if description is None:
            description, self._canvas, self._margin = astronaut_scene(width, height)
        else:
            if description.texture.shape[:2] != (height, width):
                raise ValueError(
                    f"description texture is {description.texture.shape[1]}x"
                    f"{description.texture.shape[0]}, frames are {width}x{height}"
                )
            self._canvas, self._margin = _bgr(description.texture), 0
        self.description = description
        self.model = description.model
        self.template_points = description.projected()
        self.scene = SceneMesh.build(self.model, description.params, (height, width))
        # Where every scene point sits on the canvas at the template pose.
        self._scene_template = self.scene.points(description.params) + self._margin
        frontal = self.scene.normals(self.description.params)[:, 2]
        self._template_shade = AMBIENT + (1 - AMBIENT) * np.clip(frontal, 0, None)
        self._plan = _speech_plan(np.random.default_rng(seed), self.motion)
        self.fap = fap
        self._fap_params = None
        if fap is not None:
            if len(fap) == 0:
                raise ValueError(f"{fap.name}: the .fap sequence holds no frame")
            units = fap_units(self.model)
            base = self.description.params
            self._fap_params = np.array(
                [faps_to_parameters(f, self.model, units, base=base) for f in fap.frames]
            )

    def params_at(self, index: int) -> np.ndarray:
        """The model parameters of frame `index` (6 + A,)."""
        if self._fap_params is not None:
            return self._fap_params[min(index, len(self._fap_params) - 1)].copy()
        m, t = self.motion, index / self.fps
        base = self.description.params
        p = base.copy()
        p[0] += m.shift_frac * self.width * np.sin(2 * np.pi * 0.07 * t + 0.3)
        p[1] += 0.6 * m.shift_frac * self.width * np.sin(2 * np.pi * 0.11 * t + 1.1)
        p[2] *= 1.0 + m.scale_frac * np.sin(2 * np.pi * 0.05 * t)
        p[3] += m.pitch_rad * np.sin(2 * np.pi * 0.23 * t + 0.5)
        p[4] += m.yaw_rad * np.sin(2 * np.pi * 0.13 * t)
        p[5] += m.roll_rad * np.sin(2 * np.pi * 0.17 * t + 2.0)
        names = self.model.action_unit_names
        actions = p[N_POSE:]
        mouth = m.speech * _speech_level(self._plan, t)
        if "jaw_drop" in names:
            actions[names.index("jaw_drop")] += 0.6 * mouth
        if "lip_stretch" in names:
            actions[names.index("lip_stretch")] += 0.3 * mouth * np.sin(2 * np.pi * 1.3 * t)
        if "brow_raise" in names:
            actions[names.index("brow_raise")] += 0.3 * max(0.0, np.sin(2 * np.pi * 0.09 * t)) ** 4
        if m.blinks and "eye_close" in names:
            actions[names.index("eye_close")] = max(
                actions[names.index("eye_close")], _blink(self._plan, t)
            )
        return p

    def light_at(self, index: int) -> tuple[float, np.ndarray]:
        """Overall gain and the key light's unit direction (camera coordinates) at frame `index`.

        At frame 0 the light is the template's own: gain 1, shining along the camera's axis
        (and at every frame when a `.fap` file drives the head).
        """
        if self._fap_params is not None:
            return 1.0, np.array([0.0, 0.0, 1.0])
        m, t = self.motion, index / self.fps
        gain = 1.0 + m.light_gain * np.sin(2 * np.pi * 0.04 * t)
        tilt = m.light_angle_rad * np.sin(np.pi * 0.035 * t) ** 2
        turn = 2 * np.pi * 0.03 * t
        direction = np.array(
            [np.sin(tilt) * np.cos(turn), np.sin(tilt) * np.sin(turn), np.cos(tilt)]
        )
        return float(gain), direction

    def ground_truth(self, index: int) -> dict:
        """Parameters, projected model points (N, 2) and light (gain, direction) of frame `index`."""
        params = self.params_at(index)
        gain, direction = self.light_at(index)
        return {
            "frame": index,
            "params": params,
            "points": project(self.model, params),
            "light_gain": gain,
            "light_direction": direction,
        }

    def render_bgr(self, index: int, *, rng: np.random.Generator | None = None) -> np.ndarray:
        """Frame `index` as a BGR image (lighting and, with `rng`, noise applied).

        Every pixel takes the affine map of the scene triangle drawn there (nearest triangle
        first): where on the canvas to sample, and how much the light changes it. The maps
        (compiled, `uma.face.talking_head_kernels`) and one cv2.remap make the frame.
        """
        import cv2

        from uma.face.talking_head_kernels import light_and_noise, pixel_maps

        params = self.params_at(index)
        scene = self.scene
        target = scene.points(params)
        triangles = scene.triangles
        labels = triangle_labels(
            target,
            triangles,
            (self.height, self.width),
            triangle_mask=_front_facing(target, triangles),
            depth=scene.depth(params),
        )
        gain, direction = self.light_at(index)
        values = np.column_stack([self._scene_template, self._shading(params, direction)])
        coeffs = np.einsum("tjk,tjc->tck", barycentric_affine(target, triangles), values[triangles])
        # A pixel no triangle covers (a strip folded over at an extreme pose) keeps the template.
        m = self._margin
        still = np.array([[[1.0, 0.0, m], [0.0, 1.0, m], [0.0, 0.0, 1.0]]])
        table = np.ascontiguousarray(np.concatenate([coeffs, still]).astype(np.float32))
        map_x, map_y, light = pixel_maps(table, labels)  # label -1: the last row
        sampled = cv2.remap(
            self._canvas, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
        )
        noisy = rng is not None and self.motion.noise_std > 0
        shape = sampled.shape if noisy else (0, 0, 0)
        noise = rng.standard_normal(shape, dtype=np.float32) if noisy else _NO_NOISE
        std = np.float32(self.motion.noise_std)
        return light_and_noise(sampled, light, np.float32(gain), noise, std)

    def _shading(self, params: np.ndarray, direction: np.ndarray) -> np.ndarray:
        """Per scene point: brightness under `direction` relative to the template's lighting."""
        factors = np.ones(self.scene.n_points)
        if self.motion.light_angle_rad == 0:
            return factors
        lit = AMBIENT + (1 - AMBIENT) * np.clip(self.scene.normals(params) @ direction, 0, None)
        face = lit / self._template_shade
        factors[: self.model.n_vertices] = face
        ring = slice(self.model.n_vertices, self.model.n_vertices + len(self.scene.outline))
        factors[ring] = face[self.scene.outline]  # hair and ears lit like the face's edge
        return factors

    def frames(self) -> Iterator[np.ndarray]:
        import cv2

        rng = np.random.default_rng(self.seed)
        index = 0
        while self.frame_count is None or index < self.frame_count:
            bgr = self.render_bgr(index, rng=rng)
            yield cv2.cvtColor(bgr, cv2.COLOR_BGR2YUV_I420)
            index += 1


_NO_NOISE = np.empty((0, 0, 0), np.float32)


def _speech_plan(rng: np.random.Generator, motion: Motion) -> dict:
    # Phrases of 1.5-4 s separated by 0.5-1.5 s pauses; blinks every 2-6 s; ten minutes' worth.
    phrases, t = [], 0.5
    while t < 600:
        length = rng.uniform(1.5, 4.0)
        phrases.append((t, t + length, rng.uniform(3.0, 5.0), rng.uniform(0, 2 * np.pi)))
        t += length + rng.uniform(0.5, 1.5)
    blinks = np.cumsum(rng.uniform(2.0, 6.0, 200))
    return {"phrases": phrases, "blinks": blinks}


def _speech_level(plan: dict, t: float) -> float:
    for start, end, rate_hz, phase in plan["phrases"]:
        if start <= t < end:
            envelope = np.sin(np.pi * (t - start) / (end - start)) ** 0.5
            return float(envelope * 0.5 * (1 - np.cos(2 * np.pi * rate_hz * (t - start) + phase)))
        if start > t:
            break
    return 0.0


def _blink(plan: dict, t: float) -> float:
    blinks = plan["blinks"]
    k = np.searchsorted(blinks, t)
    nearest = min((abs(t - blinks[j]) for j in (k - 1, k) if 0 <= j < len(blinks)), default=1.0)
    return float(max(0.0, 1.0 - nearest / 0.08))  # a 160 ms blink


def _front_facing(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    a, b, c = (points[triangles[:, k]] for k in range(3))
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    return cross < 0  # counter-clockwise from the front turns clockwise with y down


def _bgr(image: np.ndarray) -> np.ndarray:
    import cv2

    return cv2.cvtColor(image, cv2.COLOR_GRAY2BGR) if image.ndim == 2 else image
