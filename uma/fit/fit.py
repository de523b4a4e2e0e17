"""Initialise the face model on an image: detector, search box, method, and failure values.

Units: pixels, radians. `fit_face` is what the engine calls when it switches to the model-based
codec: it checks the image, lets the face detector place the search, runs the chosen method
(SAABs, SAABs with illumination compensation, Gauss-Newton, or the hybrid: SAABs' global pose
search in two views of the images, a third when the match is poor, the best polished by
Gauss-Newton; `uma.fit.hybrid`) and returns a `FitResult`, or a `Failure` that says why.
`saabs_config.illumination` is set by the method ("saabs": off, "saabs_ic": on; the hybrid's
stages set their own).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from uma.face.detect import Box, detect_face, detect_faces
from uma.failure import Failure
from uma.fit.cost import Cost, FitTemplate
from uma.fit.gauss_newton import GaussNewtonConfig, gauss_newton
from uma.fit.hybrid import HybridConfig, hybrid
from uma.fit.result import FitResult
from uma.fit.saabs import SaabsConfig, saabs
from uma.fit.search import SearchBox, search_box

__all__ = [
    "fit_face",
    "initial_guess",
    "turned_guess",
    "small_guess",
    "detect",
    "DETECTOR_ROLLS_RAD",
    "DetectorCalibration",
    "METHODS",
    "check_image",
]

METHODS = ("saabs", "saabs_ic", "gauss_newton", "hybrid")
# A fit whose correlation with the template stays below this found no face.
MIN_CORRELATION = 0.3


@dataclass(frozen=True)
class DetectorCalibration:
    """How the template's own detection box relates to its model placement (box widths)."""

    dx: float
    dy: float
    scale: float

    @classmethod
    def from_template(cls, template: FitTemplate, box: Box) -> DetectorCalibration:
        cx, cy = box.centre
        p = template.params
        return cls((p[0] - cx) / box.width, (p[1] - cy) / box.width, p[2] / box.width)


def check_image(image: np.ndarray) -> Failure | None:
    """Why an image cannot be fitted (wrong kind, flat, saturated), or None."""
    if image.ndim != 2 or image.shape[0] < 16 or image.shape[1] < 16:
        return Failure(f"expected a gray image of at least 16x16, got shape {image.shape}")
    if image.dtype == np.uint8:  # a picture: finite, and cheap to measure as it is
        import cv2

        spread = float(cv2.meanStdDev(image)[1][0, 0])
        saturated = np.count_nonzero((image <= 2) | (image >= 253)) / image.size
    else:
        values = np.asarray(image, dtype=np.float32)
        if not np.all(np.isfinite(values)):
            return Failure("image holds NaN or infinite values")
        spread = float(values.std())
        saturated = float(np.mean((values <= 2) | (values >= 253)))
    if spread < 2.0:
        return Failure("image is flat: nothing to fit")
    if saturated > 0.9:
        return Failure("image is saturated: nothing to fit")
    return None


DETECTOR_SIDE_PX = 144  # the detector looks at the image scaled so its shorter side is this
CASCADE_MIN_PX = 24  # the cascade's own smallest face


def _scale(shape: tuple[int, ...]) -> float:
    """What `detect` scales a picture of `shape` by (at most 1)."""
    return min(1.0, DETECTOR_SIDE_PX / min(shape[:2]))


def _scaled_min_px(shape: tuple[int, ...]) -> int:
    """The smallest face `detect` looks for, in pixels of its scaled picture."""
    return max(CASCADE_MIN_PX, round(min(shape[:2]) * _scale(shape)) // 5)


def detect(image: np.ndarray) -> Box | Failure:
    """The face detector's box on `image` (pixels of `image`). Large images are searched at a
    shorter side of DETECTOR_SIDE_PX: faces filling a fifth of the picture or more stay over
    the cascade's 24-px minimum, and a CIF frame costs ~4 ms instead of ~17 (a smaller face:
    `small_guess`)."""
    import cv2

    gray = np.clip(np.nan_to_num(image), 0, 255).astype(np.uint8)
    factor = _scale(gray.shape)
    small = gray
    if factor < 1.0:
        size = (round(gray.shape[1] * factor), round(gray.shape[0] * factor))
        small = cv2.resize(gray, size, interpolation=cv2.INTER_AREA)
    box = detect_face(small, min_size_px=_scaled_min_px(gray.shape), neighbours=3)
    if not box or factor == 1.0:
        return box
    sx, sy = gray.shape[1] / small.shape[1], gray.shape[0] / small.shape[0]
    return Box(round(box.x * sx), round(box.y * sy), round(box.width * sx), round(box.height * sy))


def initial_guess(
    template: FitTemplate, image: np.ndarray, calibration: DetectorCalibration | None
) -> tuple[np.ndarray, SearchBox] | Failure:
    """Start and search box from the face detector on `image`; without a calibration (the
    template's own box), the template's placement is the start."""
    if calibration is None:
        start = template.params.copy()
        return start, search_box(start, template.face_width_px)
    box = detect(image)
    if not box:
        return Failure(f"no face found ({box.reason})")
    return _guess_from_box(template, calibration, box)


def _guess_from_box(
    template: FitTemplate, calibration: DetectorCalibration, box: Box
) -> tuple[np.ndarray, SearchBox]:
    """The upright start the detector's `box` says (`calibration`'s offset and scale) and the
    search box about it."""
    start = template.params.copy()
    cx, cy = box.centre
    start[0] = cx + calibration.dx * box.width
    start[1] = cy + calibration.dy * box.width
    start[2] = calibration.scale * box.width
    start[3:6] = 0.0
    return start, search_box(start, template.face_width_px * start[2] / template.params[2])


def small_guess(
    template: FitTemplate, image: np.ndarray, calibration: DetectorCalibration
) -> tuple[np.ndarray, SearchBox] | Failure:
    """Start and search box from the detector on `image` at its own size, for an upright face
    smaller than `detect` looks for (a wide shot: under a fifth of the picture's shorter side,
    scaled to DETECTOR_SIDE_PX); of several, the one nearest the description's own size. The
    whole picture at full size costs several times `detect`: the initialisation asks last."""
    gray = np.clip(np.nan_to_num(image), 0, 255).astype(np.uint8)
    found = detect_faces(gray, min_size_px=CASCADE_MIN_PX, neighbours=3)
    if not found:
        return Failure(f"no small face found ({found.reason})")
    smallest_px = _scaled_min_px(gray.shape) / _scale(gray.shape)  # what `detect` finds, here
    small = [box for box in found if box.width < smallest_px]
    if not small:
        return Failure("no face smaller than the scaled search's smallest")
    expected_px = template.params[2] / calibration.scale  # the description's box width
    box = min(small, key=lambda b: abs(np.log(b.width / expected_px)))
    return _guess_from_box(template, calibration, box)


# Where the upright detector found no face (OpenCV's cascade is trained on upright faces),
# `turned_guess` looks on copies of the image turned by these: a head tilted to a shoulder.
# It missed the talking head rolled by 0.45 rad, and one rolled by 0.8 on the copy turned by 0.5.
DETECTOR_ROLLS_RAD = (0.5, -0.5, 0.9, -0.9)


def turned_guess(
    template: FitTemplate, image: np.ndarray, calibration: DetectorCalibration
) -> tuple[np.ndarray, SearchBox] | Failure:
    """Start and search box from the detector on copies of `image` turned by each of
    DETECTOR_ROLLS_RAD in turn, the first that holds a face: the box's offset to the model
    (`calibration`) taken in the turned copy, the start rolled by that angle and the search's
    roll about it. For a face the upright detector missed; an upright face it missed too may
    be found here at a wrong roll, so `initial_guess` does not call it."""
    import cv2

    height, width = image.shape
    turn_about = (width / 2.0, height / 2.0)
    gray = np.clip(np.nan_to_num(image), 0, 255).astype(np.uint8)
    for roll in DETECTOR_ROLLS_RAD:
        # OpenCV turns by degrees counter-clockwise (y down): -roll sets a face rolled by
        # `roll` upright.
        turn = cv2.getRotationMatrix2D(turn_about, -float(np.degrees(roll)), 1.0)
        turned = cv2.warpAffine(gray, turn, (width, height), borderMode=cv2.BORDER_REPLICATE)
        box = detect(turned)
        if not box:
            continue
        cx, cy = box.centre
        upright = (cx + calibration.dx * box.width, cy + calibration.dy * box.width, 1.0)
        start = template.params.copy()
        start[0], start[1] = cv2.invertAffineTransform(turn) @ np.array(upright)
        start[2] = calibration.scale * box.width
        start[3:6] = 0.0, 0.0, roll
        face_width = template.face_width_px * start[2] / template.params[2]
        return start, search_box(start, face_width, roll_rad=roll)
    return Failure(f"no face found on the image turned by {DETECTOR_ROLLS_RAD} rad")


def fit_face(
    template: FitTemplate,
    image: np.ndarray,
    *,
    method: str = "hybrid",
    start: np.ndarray | None = None,
    box: SearchBox | None = None,
    calibration: DetectorCalibration | None = None,
    saabs_config: SaabsConfig = SaabsConfig(),
    gn_config: GaussNewtonConfig = GaussNewtonConfig(),
    hybrid_config: HybridConfig = HybridConfig(),
    rng=None,
) -> FitResult | Failure:
    """Fit `template`'s model to `image`; `start`/`box` default to the detector's proposal."""
    if method not in METHODS:
        return Failure(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    problem = check_image(image)
    if problem is not None:
        return problem
    if start is None or box is None:
        guess = initial_guess(template, image, calibration)
        if not guess:
            return guess
        start, box = guess
    start = np.asarray(start, dtype=np.float64)
    if start.shape != template.params.shape or not np.all(np.isfinite(start)):
        return Failure(
            f"start: expected {template.params.size} finite parameters, got {np.shape(start)}"
        )
    rng = np.random.default_rng(rng)
    image = np.asarray(image, dtype=np.float32)
    if method == "gauss_newton":
        result = gauss_newton(template, image, start, box, config=gn_config)
    elif method == "hybrid":
        result = hybrid(
            template, image, start, box, config=hybrid_config, saabs_config=saabs_config, rng=rng
        )
    else:
        config = replace(saabs_config, illumination=method == "saabs_ic")
        cost = Cost(template, image, illumination=config.illumination)
        result = saabs(cost, start, box, config=config, rng=rng)
    if not np.all(np.isfinite(result.params)):
        return Failure("the fit diverged")
    if 1.0 - result.cost < MIN_CORRELATION:
        return Failure(
            f"no face matched: best correlation {1.0 - result.cost:.2f} < {MIN_CORRELATION}"
        )
    # A face beyond the box drags the fit onto its walls: translation or scale at a bound, or
    # the head turned and nodded to the limit at once.
    margin = 0.01 * (box.high - box.low)
    pinned = (result.params <= box.low + margin) | (result.params >= box.high - margin)
    if pinned[:3].any() or pinned[3:5].all():
        return Failure("the face lies outside the search box")
    return result
