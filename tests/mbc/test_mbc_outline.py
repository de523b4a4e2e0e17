"""The person's outline softened as the head moves (`uma.mbc.outline`)."""

from __future__ import annotations

import numpy as np

from uma.mbc.outline import OUTLINE_MAX_PX, outline_band_px, soften_outline


def _scene(centre_x: int) -> tuple[np.ndarray, np.ndarray]:
    """A dark disc (the head) on a bright textured ground, YUV 4:2:0 64x48, and its mask."""
    height, width = 48, 64
    ys, xs = np.mgrid[0:height, 0:width]
    person = (xs - centre_x) ** 2 + (ys - 24) ** 2 <= 12**2
    luma = np.where(person, 40, 200 + 20 * np.sin(xs / 3.0)).astype(np.uint8)
    picture = np.vstack([luma, np.full((height // 2, width), 128, np.uint8)])
    return picture, person


def test_band_grows_with_the_move_up_to_its_cap():
    assert outline_band_px(0.0) == 0
    assert outline_band_px(float("nan")) == 0
    assert 0 < outline_band_px(4.0) < outline_band_px(10.0) <= OUTLINE_MAX_PX
    assert outline_band_px(1000.0) == OUTLINE_MAX_PX
    assert outline_band_px(1000.0, 50.0) == 3  # a small head: 0.06 of its width


def test_a_still_head_is_left_as_drawn():
    picture, person = _scene(32)
    out = picture.copy()
    soften_outline(out, person, np.zeros_like(person), 0.0)
    assert np.array_equal(out, picture)


def test_face_and_far_pixels_kept_the_edge_nearer_an_unsure_truth():
    drawn, person = _scene(32)
    face = np.zeros_like(person)
    face[20:28, 28:36] = True
    out = drawn.copy()
    soften_outline(out, person, face, 10.0)
    assert np.array_equal(out[:48][face], drawn[:48][face])
    assert np.array_equal(out[:48, :6], drawn[:48, :6])  # far from the outline
    assert not np.array_equal(out, drawn)
    # The head truly sits a few pixels either side of where it is drawn: the softened edge
    # errs less on average than the hard one.
    errors = []
    for picture in (drawn, out):
        mse = [np.mean((_scene(x)[0][:48].astype(float) - picture[:48]) ** 2) for x in (28, 36)]
        errors.append(np.mean(mse))
    assert errors[1] < 0.9 * errors[0]


def test_half_resolution_band_weights_follow_the_full_ones():
    """The band's weights found on every other pixel and enlarged stay near the full-size
    ones (measured on this ellipse: a mean difference of 0.015-0.017 and a total within 2 %
    from a 2-px band up; a 1-px band keeps two thirds of its weight)."""
    from uma.mbc.outline import _half_res_weight, _weight

    ys, xs = np.mgrid[0:120, 0:160]
    person = (xs - 80) ** 2 / 40**2 + (ys - 60) ** 2 / 45**2 <= 1
    for band_px in (1, 2, 4, 6, 8):
        full = _weight(person, band_px)
        half, small = _half_res_weight(person, band_px)
        assert half.shape == full.shape and small.shape == (60, 80)
        assert float(np.mean(np.abs(half - full))) < 0.025
        if band_px >= 2:
            assert abs(float(half.sum()) / float(full.sum()) - 1.0) < 0.03
        far = (xs - 80) ** 2 / 12**2 + (ys - 60) ** 2 / 15**2 <= 1  # deep inside
        assert np.all(half[far] < 1e-3) and np.all(half[:, :10] == 0.0)


def test_the_softening_reads_the_half_resolution_weights(monkeypatch):
    """The drawn picture is the half-resolution weights', not the full-size ones' (and the
    face's own pixels are kept either way)."""
    from uma.mbc import outline

    drawn, person = _scene(32)
    face = np.zeros_like(person)
    face[20:28, 28:36] = True

    def full_size(box, band_px):
        weight = outline._weight(box, band_px)
        return weight, weight[0::2, 0::2].copy()

    pictures = []
    for weights in (outline._half_res_weight, full_size):
        monkeypatch.setattr(outline, "_half_res_weight", weights)
        out = drawn.copy()
        soften_outline(out, person, face, 10.0)
        assert np.array_equal(out[:48][face], drawn[:48][face])
        pictures.append(out)
    assert not np.array_equal(pictures[0], pictures[1])
