"""turned_guess: the detector on turned copies of a picture, for a head tilted toward a shoulder."""

import numpy as np
import pytest

from uma.fit.fit import DETECTOR_ROLLS_RAD, detect, initial_guess, turned_guess
from uma.fit.search import ROLL_SEARCH_RAD


def _turned(image: np.ndarray, roll: float) -> np.ndarray:
    """`image` with its content rolled by `roll` as the model rolls (about the picture's centre)."""
    import cv2

    height, width = image.shape
    turn = cv2.getRotationMatrix2D((width / 2.0, height / 2.0), float(np.degrees(roll)), 1.0)
    return cv2.warpAffine(image, turn, (width, height), borderMode=cv2.BORDER_REPLICATE)


def _upright_centre(template) -> np.ndarray:
    return np.array(template.fit.params[:2])


@pytest.mark.parametrize("roll", [0.55, -0.55])
def test_a_tilted_face_the_upright_detector_misses_is_found_turned(template, roll):
    image = _turned(template.fit.image.astype(np.float32), roll)
    assert not detect(image)  # the cascade's upright faces only
    assert not initial_guess(template.fit, image, template.calibration)
    start, box = turned_guess(template.fit, image, template.calibration)
    assert start[5] in DETECTOR_ROLLS_RAD and box.low[5] <= roll <= box.high[5]
    assert box.high[5] - box.low[5] == pytest.approx(2 * ROLL_SEARCH_RAD)
    # the model's centre, turned with the picture, within a tenth of the face's width
    height, width = image.shape
    c, s = np.cos(-roll), np.sin(-roll)  # y down: the picture turned by -roll on screen
    x, y = _upright_centre(template) - (width / 2.0, height / 2.0)
    expected = np.array([c * x - s * y, s * x + c * y]) + (width / 2.0, height / 2.0)
    assert np.hypot(*(start[:2] - expected)) < 0.1 * template.fit.face_width_px


def test_no_face_on_any_turned_copy_is_a_failure(template):
    noise = np.random.default_rng(0).uniform(0, 255, template.fit.image.shape).astype(np.float32)
    result = turned_guess(template.fit, noise, template.calibration)
    assert not result and "turned by" in result.reason
