"""The refresh's judge: its gain over the mirror's rendering, and when it need not be asked."""

import numpy as np
import pytest

from uma.mbc.refresh_judge import box_psnr_db, needs_judging, refresh_gain_db


def test_nothing_to_decide_without_a_threshold_or_before_a_first_refresh_always_sent() -> None:
    assert needs_judging(0.5, first_always=False, refresh_taken=False)
    assert needs_judging(0.5, first_always=True, refresh_taken=True)
    assert not needs_judging(0.5, first_always=True, refresh_taken=False)
    assert not needs_judging(float("-inf"), first_always=False, refresh_taken=True)
    assert needs_judging(float("inf"), first_always=False, refresh_taken=True)


def test_the_gain_is_the_box_psnr_of_the_patch_less_the_renderings(head) -> None:
    import cv2

    from uma.mbc.scene_render import SceneRenderer
    from uma.mbc.units import FaceUnits

    frame0 = cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420)
    truth = cv2.cvtColor(head.render_bgr(6), cv2.COLOR_BGR2YUV_I420)
    renderer = SceneRenderer(head.description, (352, 288))
    renderer.set_reference(frame0, head.params_at(0))
    units = FaceUnits.of(head.model, head.description.params, light=True, body=True)
    values = np.concatenate([head.params_at(6), np.zeros(3), (1.0, 0.0)])
    (x0, y0), (w, h) = (120, 80), (96, 112)
    exact = np.vstack([truth[y0 : y0 + h, x0 : x0 + w], np.zeros((h // 2, w), np.uint8)])
    rendered, _ = renderer.render(head.params_at(6), (1.0, 0.0), np.zeros(3))
    window = (slice(y0, y0 + h), slice(x0, x0 + w))
    expected = 100.0 - box_psnr_db(rendered[:288][window], truth[:288][window])
    gain = refresh_gain_db(renderer, units, values, (x0, y0), exact, truth)
    assert gain == pytest.approx(expected)
    assert gain > 10.0  # the true picture beats any rendering of it
    grey = np.full_like(exact, 128)
    assert refresh_gain_db(renderer, units, values, (x0, y0), grey, truth) < 0.0


@pytest.mark.parametrize("soften", [False, True])
def test_a_luma_only_rendering_draws_the_same_luma(head, soften: bool) -> None:
    """The judge's rendering (`luma_only`) skips the chroma, not a pixel of the luma: a moved
    head and torso, the light and the outline's softening drawn both ways."""
    import cv2

    from uma.mbc.scene_render import SceneRenderer

    renderer = SceneRenderer(head.description, (352, 288), soften_outline=soften)
    renderer.set_reference(cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420),
                           head.params_at(0))  # fmt: skip
    params = head.params_at(8).copy()
    params[0] += 4.0
    body = np.array([3.0, -2.0, 0.01])
    full, face = renderer.render(params, (1.1, -3.0), body)
    luma, luma_face = renderer.render(params, (1.1, -3.0), body, luma_only=True)
    assert renderer.layered and np.array_equal(face, luma_face)
    assert np.array_equal(luma[:288], full[:288])
    assert not np.array_equal(luma[288:], full[288:])  # the chroma was not drawn


def test_the_box_psnr_of_uint8_boxes_is_the_float64_formulas_to_the_bit() -> None:
    import math

    rng = np.random.default_rng(5)
    picture = rng.integers(0, 256, (288, 352), dtype=np.uint8)
    truth = rng.integers(0, 256, (288, 352), dtype=np.uint8)
    truth[:100] = picture[:100] // 2 + 60  # near and far boxes
    for y0, x0, h, w in ((0, 0, 288, 352), (20, 30, 91, 77), (150, 3, 1, 5), (0, 0, 64, 64)):
        a, b = picture[y0 : y0 + h, x0 : x0 + w], truth[y0 : y0 + h, x0 : x0 + w]
        mse = float(np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2))
        assert box_psnr_db(a, b) == 10.0 * math.log10(255.0**2 / mse)
        assert box_psnr_db(a.astype(np.float32), b) == box_psnr_db(a, b)
    assert box_psnr_db(picture, picture) == 100.0
    worst = box_psnr_db(np.zeros((288, 352), np.uint8), np.full((288, 352), 255, np.uint8))
    assert worst == 0.0
