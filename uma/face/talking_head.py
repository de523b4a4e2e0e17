"""A talking-head source with exact ground truth: a real face photograph animated by the model.

Units: pixels, radians, seconds; frames are planar YUV 4:2:0 (H * 3 // 2, W) uint8.

The default face is scikit-image's astronaut photograph (public domain) with the hand-clicked
feature points of `codecs/face/astronaut.yaml`. The head turns, nods and tilts, drifts and
breathes in scale; the jaw and lips move in a speech-like rhythm (syllables at ~4 Hz in
phrases with pauses); the eyes blink every few seconds; the light changes in gain and in
direction (a gradient turning across the face); the sensor adds Gaussian noise. All motion is
deterministic from the seed. `ground_truth(i)` gives the parameters and projected model points
of frame i, exactly those used to render it.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from uma.face.describe import ContentDescription, read_points
from uma.face.geometry import N_POSE, project, rotation_matrix, visible_triangles
from uma.face.render import render

__all__ = ["TalkingHeadSource", "Motion", "astronaut_description"]


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
    light_gain: float = 0.15
    light_gradient: float = 0.25
    noise_std: float = 2.0


def astronaut_description(width: int, height: int) -> ContentDescription:
    """The astronaut, cropped around her face to `width`:`height` and described from its points."""
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
    warp = np.float32([[scale, 0, -x0 * scale], [0, scale, -y0 * scale]])
    frame = cv2.warpAffine(
        image, warp, (width, height), flags=cv2.INTER_AREA, borderMode=cv2.BORDER_REFLECT
    )
    moved = {k: ((x - x0) * scale, (y - y0) * scale) for k, (x, y) in points.items()}
    # The whole frame is the texture: the talking head renders over it.
    return describe_full(frame, moved)


def describe_full(frame: np.ndarray, points) -> ContentDescription:
    """Like `describe`, but the texture is the whole frame (no crop)."""
    from uma.face.fit_points import fit_points
    from uma.face.model import load_model

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
    ) -> None:
        self.width, self.height, self.fps = width, height, float(fps)
        self.name = "talking-head"
        self.frame_count = frame_count
        self.seed = seed
        self.motion = motion or Motion()
        self.description = description or astronaut_description(width, height)
        self.model = self.description.model
        self.template_points = self.description.projected()
        self._plan = _speech_plan(np.random.default_rng(seed), self.motion)

    def params_at(self, index: int) -> np.ndarray:
        """The model parameters of frame `index` (6 + A,)."""
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

    def ground_truth(self, index: int) -> dict:
        """Parameters and projected model points of frame `index`."""
        params = self.params_at(index)
        return {"frame": index, "params": params, "points": project(self.model, params)}

    def render_bgr(self, index: int, *, rng: np.random.Generator | None = None) -> np.ndarray:
        """Frame `index` as a BGR image (lighting and, with `rng`, noise applied)."""
        params = self.params_at(index)
        target = project(self.model, params)
        rotation = rotation_matrix(params[3], params[4], params[5])
        depth = (self.model.vertices @ rotation.T)[:, 2]
        texture = self.description.texture
        frame = render(
            texture,
            self.template_points,
            target,
            self.model.triangles,
            texture.shape[:2],
            visible=visible_triangles(self.model, params),
            depth=depth,
            background=texture,
        ).image.astype(np.float32)
        frame = self._light(frame, index / self.fps, target)
        if rng is not None and self.motion.noise_std > 0:
            frame += self.motion.noise_std * rng.standard_normal(frame.shape, dtype=np.float32)
        return np.clip(np.rint(frame), 0, 255).astype(np.uint8)

    def _light(self, frame: np.ndarray, t: float, target: np.ndarray) -> np.ndarray:
        m = self.motion
        if m.light_gain == 0 and m.light_gradient == 0:
            return frame
        gain = 1.0 + m.light_gain * np.sin(2 * np.pi * 0.04 * t)
        angle = 2 * np.pi * 0.03 * t
        centre = target.mean(axis=0)
        span = max(np.ptp(target[:, 0]), 1.0)
        yy = np.arange(frame.shape[0], dtype=np.float32)[:, None] - centre[1]
        xx = np.arange(frame.shape[1], dtype=np.float32)[None, :] - centre[0]
        ramp = (xx * np.cos(angle) + yy * np.sin(angle)) / span
        light = gain * (1.0 + m.light_gradient * np.clip(ramp, -1.0, 1.0))
        return frame * (light[..., None] if frame.ndim == 3 else light)

    def frames(self) -> Iterator[np.ndarray]:
        import cv2

        rng = np.random.default_rng(self.seed)
        index = 0
        while self.frame_count is None or index < self.frame_count:
            bgr = self.render_bgr(index, rng=rng)
            yield cv2.cvtColor(bgr, cv2.COLOR_BGR2YUV_I420)
            index += 1


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
