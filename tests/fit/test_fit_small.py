"""small_guess: the detector at the picture's own size, for a face a wide shot makes small."""

import numpy as np
import pytest

from uma.fit.fit import detect, initial_guess, small_guess

PAD_PX = 250  # the astronaut's 92x112 picture in the middle of a 592x612 one


def _wide(image: np.ndarray) -> np.ndarray:
    """`image` in the middle of a larger picture shaded from dark to light (a wide shot of
    the same face: a flat surround would leave the cascade's equalised picture all one grey)."""
    height, width = image.shape
    rows, cols = np.mgrid[0 : height + 2 * PAD_PX, 0 : width + 2 * PAD_PX]
    out = (40.0 + 80.0 * cols / cols.shape[1] + 80.0 * rows / rows.shape[0]).astype(np.float32)
    out[PAD_PX : PAD_PX + height, PAD_PX : PAD_PX + width] = image
    return out


def test_a_face_too_small_for_the_scaled_search_is_found_at_full_size(template):
    image = _wide(template.fit.image.astype(np.float32))
    assert detect(template.fit.image.astype(np.float32))  # the face itself is detectable
    assert not detect(image)  # but under a fifth of the scaled picture's side
    assert not initial_guess(template.fit, image, template.calibration)
    start, box = small_guess(template.fit, image, template.calibration)
    expected = np.array(template.fit.params[:2]) + PAD_PX
    assert np.hypot(*(start[:2] - expected)) < 0.1 * template.fit.face_width_px
    assert start[2] == pytest.approx(template.fit.params[2], rel=0.2)
    assert np.all(start[3:6] == 0.0) and box.low[0] <= start[0] <= box.high[0]


def test_no_small_face_is_a_failure_naming_why(template):
    noise = np.random.default_rng(1).uniform(0, 255, (400, 400)).astype(np.float32)
    result = small_guess(template.fit, noise, template.calibration)
    assert not result and "small face" in result.reason
    # a face the scaled search already sees is not a small face
    result = small_guess(template.fit, template.fit.image.astype(np.float32), template.calibration)
    assert not result and "smaller than the scaled search" in result.reason


def test_the_tracker_initialisation_asks_for_a_small_face_last(template):
    from uma.mbc.tracking_init import InitSearch

    image = _wide(template.fit.image.astype(np.float32))
    search = InitSearch(template.fit, "hybrid", template.calibration, template.fit.params)
    fit, detections, why = search.fit(image, "first picture", None, np.random.default_rng(0))
    assert fit, fit.reason
    assert detections == 6  # upright, four turned copies, then the picture at its own size
    assert why == "first picture (a small face, found at the picture's own size)"
    expected = np.array(template.fit.params[:2]) + PAD_PX
    assert np.hypot(*(fit.params[:2] - expected)) < 2.0
