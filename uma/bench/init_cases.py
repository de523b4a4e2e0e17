"""Test cases with known ground truth for `uma bench init`, built from real face images.

Units: pixels, radians. Every case is at the paper's size, 92x112 (width x height). A template
is a real face (ORL: first image of each person; Yale B: the frontal, ambient-lit image) with
the wireframe placed on it from OpenCV's face detector and fixed proportions (ORL) or fixed
proportions of the tightly cropped Yale images; where shared data is absent, the astronaut
with her clicked points. A case renders the template's texture at a known random pose (yaw and
pitch up to 20 deg, roll up to 15, scale +-15 %, shifts up to 10 % of the face width) and mild
expression, over the template's own background moved by the same 2-D motion; Yale cases take
the texture from the same face lit from another direction (pixel-aligned, so the light really
changes); all cases add sensor noise. Ground truth is exact: the parameters used to render.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uma.face.detect import detect_face
from uma.face.geometry import make_params, project, rotation_matrix, visible_triangles
from uma.face.model import FaceModel
from uma.face.render import render
from uma.fit.cost import FitTemplate
from uma.fit.fit import DetectorCalibration, detect

__all__ = [
    "Template",
    "Case",
    "load_templates",
    "make_cases",
    "IMAGE_SIZE",
    "is_large_pose",
    "rotation_deg",
    "light_angle_deg",
]

IMAGE_SIZE = (92, 112)  # width, height
IMAGE_EXTENSIONS = (".pgm", ".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")


@dataclass(frozen=True, eq=False)
class Template:
    name: str
    fit: FitTemplate
    calibration: DetectorCalibration | None
    lightings: tuple[np.ndarray, ...] = ()  # the same face under other lights, aligned
    lighting_names: tuple[str, ...] = ()  # e.g. "A-035E+20": light azimuth and elevation, deg


@dataclass(frozen=True, eq=False)
class Case:
    name: str
    template: Template
    image: np.ndarray  # uint8 (112, 92)
    truth: np.ndarray
    yaw_deg: float
    pitch_deg: float
    roll_deg: float
    shift_frac: float
    lighting: str


LARGE_ROTATION_DEG = 20.0
LARGE_SHIFT = 0.08  # of the face width


def rotation_deg(case: Case) -> float:
    """Angle of the rotation taking the template's pose to the case's (yaw, pitch, roll together)."""
    base = rotation_matrix(*case.template.fit.params[3:6])
    turned = rotation_matrix(*case.truth[3:6])
    cosine = (np.trace(turned @ base.T) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))


def is_large_pose(case: Case) -> bool:
    """Large pose: the head turned by more than 20 degrees from the template's pose (yaw, pitch
    and roll combined), or shifted by more than 8 % of the face width along x or y."""
    return rotation_deg(case) > LARGE_ROTATION_DEG or case.shift_frac > LARGE_SHIFT


def light_angle_deg(lighting: str) -> float | None:
    """Angle between a Yale B light ("A+035E-20": azimuth, elevation) and the camera axis."""
    from uma.bench.init_yale import light_angles_deg

    angles = light_angles_deg(lighting) if lighting != "same" else None
    if angles is None:
        return None
    azimuth, elevation = np.radians(angles)
    return round(float(np.degrees(np.arccos(np.cos(azimuth) * np.cos(elevation)))), 1)


def _read_gray(path: Path) -> np.ndarray | None:
    import cv2

    image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if image is None:
        return None
    return cv2.resize(image, IMAGE_SIZE, interpolation=cv2.INTER_AREA)


def _calibrated(
    name: str, model: FaceModel, gray: np.ndarray, params: np.ndarray, lightings=()
) -> Template:
    """A template and how its detection box relates to its placement; `lightings` are
    (light name, image) pairs of the same face under other lights, aligned with `gray`."""
    fit = FitTemplate.build(model, gray, params)
    box = detect(gray)
    calibration = DetectorCalibration.from_template(fit, box) if box else None
    return Template(
        name=name,
        fit=fit,
        calibration=calibration,
        lightings=tuple(image for _, image in lightings),
        lighting_names=tuple(name for name, _ in lightings),
    )


def _orl_templates(model: FaceModel, folder: Path, limit: int) -> list[Template]:
    out = []
    for person in sorted(p for p in folder.iterdir() if p.is_dir()):
        images = sorted(f for f in person.iterdir() if f.suffix.lower() in IMAGE_EXTENSIONS)
        if not images:
            continue
        gray = _read_gray(images[0])
        if gray is None:
            continue
        box = detect_face(gray, min_size_px=30, neighbours=3)
        if not box:
            continue
        cx, cy = box.centre
        params = make_params(
            model, tx_px=cx, ty_px=cy - 0.01 * box.width, scale_px=0.70 * box.width
        )
        out.append(_calibrated(f"{folder.name}/{person.name}", model, gray, params))
        if len(out) >= limit:
            break
    return out


def _yale_templates(model: FaceModel, folder: Path) -> list[Template]:
    from uma.bench.init_yale import canvas, placement, read_full, read_registered_lights

    out = []
    for person in sorted(p for p in [folder, *folder.iterdir()] if p.is_dir()):
        images = sorted(person.glob("*_P00A*.pgm"))
        frontal = [f for f in images if "A+000E+00" in f.name]
        reference = read_full(frontal[0]) if frontal else None
        if reference is None:
            continue
        gray = canvas(reference, IMAGE_SIZE)
        lights = read_registered_lights(reference, images, IMAGE_SIZE)
        tx, ty, scale = placement()
        params = make_params(model, tx_px=tx, ty_px=ty, scale_px=scale)
        template = _calibrated(f"yale_b/{person.name}", model, gray, params, lights)
        out.append(template)
    return out


def _astronaut_template(model: FaceModel) -> Template:
    import cv2
    import skimage.data

    from uma.face.describe import read_points
    from uma.face.fit_points import fit_points
    from uma.paths import codecs_dir

    gray = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2GRAY)
    x0, y0, w, h = 170, 50, 110, 134  # around the face, at 92:112
    crop = cv2.resize(gray[y0 : y0 + h, x0 : x0 + w], IMAGE_SIZE, interpolation=cv2.INTER_AREA)
    sx, sy = IMAGE_SIZE[0] / w, IMAGE_SIZE[1] / h
    points = {
        k: ((x - x0) * sx, (y - y0) * sy)
        for k, (x, y) in read_points(codecs_dir() / "face" / "astronaut.yaml").items()
    }
    fit = fit_points(model, points, fit_shape=False, fit_actions=False)
    return _calibrated("astronaut", model, crop, fit.params)


def load_templates(
    model: FaceModel, *, faces: Path | None, yale: Path | None, limit: int = 20
) -> list[Template]:
    """Templates from an ORL-layout folder and a Yale B folder; the astronaut when neither exists.
    A folder that exists but yields no template is an error (FaceError) naming it."""
    from uma.errors import FaceError

    orl = _orl_templates(model, faces, limit) if faces is not None and faces.is_dir() else []
    lit = _yale_templates(model, yale) if yale is not None and yale.is_dir() else []
    if faces is not None and faces.is_dir() and not orl:
        raise FaceError(
            f"{faces}: no face found; expected one folder per person with PGM, PNG or JPEG "
            "images, the first of each showing a frontal face"
        )
    if yale is not None and yale.is_dir() and not lit:
        raise FaceError(
            f"{yale}: no Yale B images; expected *_P00A+000E+00.pgm (frontal light) and other "
            "*_P00A...E....pgm images of the same person, in the folder or its sub-folders"
        )
    if not orl and not lit:
        return [_astronaut_template(model)]
    # Interleave so every few cases include a change of light (Yale) among the ORL faces.
    templates: list[Template] = []
    for index, template in enumerate(orl):
        templates.append(template)
        if lit and index % 3 == 2:
            templates.append(lit[(index // 3) % len(lit)])
    return templates or lit


def _render_case(
    template: Template, truth: np.ndarray, texture: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    import cv2

    model, p0 = template.fit.model, template.fit.params
    # The background follows the head's 2-D motion (scale, roll, shift).
    ratio = truth[2] / p0[2]
    roll = np.degrees(truth[5] - p0[5])
    warp = cv2.getRotationMatrix2D((float(p0[0]), float(p0[1])), -roll, float(ratio))
    warp[:, 2] += truth[:2] - p0[:2]
    background = cv2.warpAffine(
        texture, warp, IMAGE_SIZE, flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT
    )
    depth = (model.vertices @ rotation_matrix(*truth[3:6]).T)[:, 2]
    image = render(
        texture,
        project(model, p0),
        project(model, truth),
        model.triangles,
        (IMAGE_SIZE[1], IMAGE_SIZE[0]),
        visible=visible_triangles(model, truth),
        depth=depth,
        background=background,
    ).image.astype(np.float32)
    image += 2.0 * rng.standard_normal(image.shape).astype(np.float32)
    return np.clip(np.rint(image), 0, 255).astype(np.uint8)


def make_cases(templates: list[Template], count: int, *, rng) -> list[Case]:
    """`count` cases over the templates in turn, each at a random known pose."""
    rng = np.random.default_rng(rng)
    cases = []
    for index in range(count):
        template = templates[index % len(templates)]
        model, p0 = template.fit.model, template.fit.params
        yaw, pitch = rng.uniform(-20, 20, 2)
        roll = rng.uniform(-15, 15)
        shift = rng.uniform(-0.10, 0.10, 2)
        truth = p0.copy()
        truth[0:2] += shift * template.fit.face_width_px
        truth[2] *= rng.uniform(0.85, 1.15)
        truth[3:6] += np.radians([pitch, yaw, roll])
        names = model.action_unit_names
        for unit, high in (("jaw_drop", 0.3), ("brow_raise", 0.3)):
            if unit in names:
                truth[6 + names.index(unit)] += rng.uniform(0.0, high)
        texture, lighting = template.fit.image.astype(np.uint8), "same"
        if template.lightings:
            pick = int(rng.integers(len(template.lightings)))
            texture, lighting = template.lightings[pick], template.lighting_names[pick]
        cases.append(
            Case(
                name=f"{template.name}#{index}",
                template=template,
                image=_render_case(template, truth, texture, rng),
                truth=truth,
                yaw_deg=float(yaw),
                pitch_deg=float(pitch),
                roll_deg=float(roll),
                shift_frac=float(np.max(np.abs(shift))),
                lighting=lighting,
            )
        )
    return cases
