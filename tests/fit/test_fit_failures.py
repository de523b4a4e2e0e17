"""fit_face on good and bad input: a result, or a failure that tests false and says why."""

import numpy as np
import pytest

from uma.fit import fit_face, mde_px, search_box
from uma.fit.cost import FitTemplate
from uma.fit.fit import METHODS, DetectorCalibration


@pytest.mark.parametrize("method", METHODS)
def test_every_method_fits_a_known_pose(template, cases, method):
    model = template.fit.model
    box = search_box(template.fit.params, template.fit.face_width_px)
    errors = []
    for seed, case in enumerate(cases):
        result = fit_face(
            template.fit,
            case.image.astype(np.float32),
            method=method,
            start=template.fit.params,
            box=box,
            rng=seed,
        )
        assert result and np.all(np.isfinite(result.params)) and result.evaluations > 0
        errors.append(mde_px(model, result.params, case.truth))
    if method in ("hybrid", "saabs_ic"):
        assert np.median(errors) < 0.5
    elif method == "saabs":
        assert np.median(errors) < 1.0


@pytest.mark.parametrize(
    "image, reason",
    [
        (np.full((112, 92), 128, np.float32), "flat"),
        (np.where(np.arange(92) % 2, 255, 0) * np.ones((112, 1), np.float32), "saturated"),
        (np.full((8, 8), 1, np.float32), "at least 16x16"),
        (np.full((112, 92), np.nan, np.float32), "NaN"),
        (np.zeros((112, 92, 3), np.float32), "gray image"),
    ],
)
def test_bad_images_fail_with_a_reason(template, image, reason):
    for method in METHODS:
        result = fit_face(template.fit, image, method=method)
        assert not result and reason in result.reason


def test_no_face_found_is_a_failure(template):
    noise = np.random.default_rng(0).uniform(0, 255, (112, 92)).astype(np.float32)
    fake = FitTemplate.build(template.fit.model, template.fit.image, template.fit.params)
    result = fit_face(fake, noise, calibration=DetectorCalibration(0.0, 0.0, 0.7))
    assert not result and "no face" in result.reason


@pytest.mark.parametrize("method", METHODS)
def test_face_outside_the_search_box_is_a_failure(template, cases, method):
    case = cases[0]
    start = template.fit.params.copy()
    start[0] += 0.6 * template.fit.face_width_px  # the box ends far from the face
    box = search_box(start, template.fit.face_width_px, shift=0.05)
    result = fit_face(
        template.fit, case.image.astype(np.float32), method=method, start=start, box=box, rng=0
    )
    assert not result
    assert "outside the search box" in result.reason or "no face matched" in result.reason


def test_unusable_start_or_method_is_a_failure(template, cases):
    image = cases[0].image.astype(np.float32)
    box = search_box(template.fit.params, template.fit.face_width_px)
    start = template.fit.params.copy()
    start[2] = np.nan
    assert "finite" in fit_face(template.fit, image, start=start, box=box).reason
    assert "unknown method" in fit_face(template.fit, image, method="magic").reason


def test_large_images_are_detected_at_reduced_size(template):
    import cv2

    from uma.fit.fit import detect

    face = template.fit.image
    small = detect(face)
    assert small  # the astronaut's 92x112 crop, searched as it is
    big = cv2.resize(face, None, fx=3, fy=3, interpolation=cv2.INTER_CUBIC)
    found = detect(big)
    assert found
    # The same face, in the big picture's pixels.
    assert found.width == pytest.approx(3 * small.width, rel=0.25)
    assert found.centre[0] == pytest.approx(3 * small.centre[0] + 1, abs=0.1 * found.width)
    assert found.centre[1] == pytest.approx(3 * small.centre[1] + 1, abs=0.1 * found.width)
