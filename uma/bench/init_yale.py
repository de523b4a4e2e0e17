"""Yale B lighting images for `uma bench init`, registered to the template they relight.

Units: pixels. The Cropped Extended Yale B images of one person share a pose but are not
pixel-aligned: between shots the head moves by up to about 2 px at 168x192 (measured here by
phase correlation and by ECC against the frontally lit image). Rendering a case with another
light's texture at the template's placement would then carry that shift into the ground truth.
Each lit image is therefore registered to the template (a translation found by OpenCV's ECC on
difference-of-Gaussians images of the log intensity, which shading changes little) and shifted
onto it at full resolution before it is scaled to the benchmark's size. The registration
itself is uncertain by about 0.3 px at 168x192 (0.15 px at 92x112) under the harsher lights.

The crops are tight (eyebrows to chin, cheek to cheek) while the wireframe reaches the hairline
and the face's outline: scaled to 92x112 as they are, the model would overhang the image by a
fifth on every side and a moving head would show texture that does not exist. So each crop is
scaled by `CROP_SCALE` (the face as large as an ORL face, about 78 px wide), set in a 92x112
canvas at `CROP_OFFSET_PX`, and the canvas around it is filled by inpainting (OpenCV's Telea
method: a smooth continuation of the border, no artificial edge).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

__all__ = ["light_angles_deg", "read_registered_lights", "read_full", "canvas", "placement"]

MAX_AZIMUTH_DEG = 60.0
MAX_ELEVATION_DEG = 45.0
CROP_SCALE = 0.375  # 168x192 -> 63x72
CROP_OFFSET_PX = (15, 25)  # where the crop's top-left corner sits in the canvas
# The model on a Yale B crop, in the crop's own pixels (centre, scale), placed by eye.
CROP_PLACEMENT_PX = (84.0, 87.5, 150.0)


def canvas(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """A full-resolution crop scaled and set in a `size` (width, height) canvas, uint8."""
    import cv2

    width = round(image.shape[1] * CROP_SCALE)
    height = round(image.shape[0] * CROP_SCALE)
    small = cv2.resize(image, (width, height), interpolation=cv2.INTER_AREA)
    out = np.zeros((size[1], size[0]), dtype=np.uint8)
    hole = np.full(out.shape, 255, dtype=np.uint8)
    x0, y0 = CROP_OFFSET_PX
    out[y0 : y0 + height, x0 : x0 + width] = np.clip(np.rint(small), 0, 255).astype(np.uint8)
    hole[y0 : y0 + height, x0 : x0 + width] = 0
    return cv2.inpaint(out, hole, 5, cv2.INPAINT_TELEA)


def placement(size_scale: float = CROP_SCALE) -> tuple[float, float, float]:
    """(tx_px, ty_px, scale_px) of the model on a crop set in the canvas."""
    cx, cy, scale = CROP_PLACEMENT_PX
    # Pixel centres: x_small = (x_big + 0.5) * f - 0.5.
    return (
        CROP_OFFSET_PX[0] + (cx + 0.5) * size_scale - 0.5,
        CROP_OFFSET_PX[1] + (cy + 0.5) * size_scale - 0.5,
        scale * size_scale,
    )


def light_angles_deg(name: str) -> tuple[float, float] | None:
    """(azimuth, elevation) of a Yale B file name such as `yaleB01_P00A-035E+20.pgm`."""
    match = re.search(r"A([+-]\d+)E([+-]\d+)", name)
    return (float(match.group(1)), float(match.group(2))) if match else None


def read_full(path: Path) -> np.ndarray | None:
    import cv2

    image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    return None if image is None else image.astype(np.float32)


def _band(image: np.ndarray) -> np.ndarray:
    import cv2

    log = np.log1p(image)
    return cv2.GaussianBlur(log, (0, 0), 1.0) - cv2.GaussianBlur(log, (0, 0), 4.0)


def _register(reference: np.ndarray, moving: np.ndarray) -> np.ndarray | None:
    """Translation (dx, dy) with moving(x + d) ~ reference(x), or None when ECC fails."""
    import cv2

    warp = np.eye(2, 3, dtype=np.float32)
    criteria = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 200, 1e-6)
    try:
        _, warp = cv2.findTransformECC(
            _band(reference), _band(moving), warp, cv2.MOTION_TRANSLATION, criteria, None, 5
        )
    except cv2.error:
        return None
    shift = warp[:, 2].astype(np.float64)
    return shift if np.all(np.isfinite(shift)) and np.abs(shift).max() < 6.0 else None


def read_registered_lights(
    reference: np.ndarray, paths: list[Path], size: tuple[int, int]
) -> list[tuple[str, np.ndarray]]:
    """The images at `paths` lit within the azimuth and elevation limits, each registered to
    `reference` (full resolution) and set in a `size` (width, height) canvas: (light, uint8)."""
    import cv2

    out = []
    for path in paths:
        angles = light_angles_deg(path.name)
        if angles is None or angles == (0.0, 0.0):
            continue
        if abs(angles[0]) > MAX_AZIMUTH_DEG or abs(angles[1]) > MAX_ELEVATION_DEG:
            continue
        image = read_full(path)
        if image is None or image.shape != reference.shape:
            continue
        shift = _register(reference, image)
        if shift is None:
            continue
        aligned = cv2.warpAffine(
            image,
            np.array([[1.0, 0.0, shift[0]], [0.0, 1.0, shift[1]]], dtype=np.float32),
            (image.shape[1], image.shape[0]),
            flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
            borderMode=cv2.BORDER_REFLECT,
        )
        name = f"A{angles[0]:+04.0f}E{angles[1]:+03.0f}"
        out.append((name, canvas(aligned, size)))
    return out
