"""The residual refresh: the engine codes the source minus its rendering in the face box, the
receiver adds the decoded residual to its own rendering; both ends then hold one picture."""

import numpy as np
import pytest


def _yuv(head, index: int) -> np.ndarray:
    import cv2

    return cv2.cvtColor(head.render_bgr(index), cv2.COLOR_BGR2YUV_I420)


@pytest.fixture(scope="module")
def scene(head):
    from uma.mbc.scene_render import SceneRenderer
    from uma.mbc.units import FaceUnits

    units = FaceUnits.of(head.model, head.description.params, light=True, body=True)

    def renderer():
        out = SceneRenderer(head.description, (352, 288))
        out.set_reference(_yuv(head, 0), head.params_at(0))
        return out

    return units, renderer


def _coder(head, params):
    from uma.mbc.refresh_coder import RefreshCoder, box_corner, even_px, face_box_size
    from uma.video import load_ladder

    box = face_box_size(head.model, params, 1.6, (352, 288))
    coded = tuple(even_px(v * 0.5) for v in box)
    settings = load_ladder().encoder.kwargs()
    coder = RefreshCoder((352, 288), coded, 5.0, 14.0, settings, box)
    return coder, box_corner(head.model, params, box, (352, 288))


def test_both_ends_hold_the_same_picture_and_it_is_nearer_the_source(head, scene) -> None:
    from uma.mbc.refresh_coder import ResidualBox, take_refresh
    from uma.mbc.refresh_judge import box_psnr_db, residual_gain_db

    units, renderer = scene
    engine, receiver = renderer(), renderer()
    coder, _ = _coder(head, head.params_at(0))
    for index in (20, 40):  # a P chain: the second residual predicted from the first
        values = np.concatenate([head.params_at(index), np.zeros(3), (1.0, 0.0)])
        params, light = units.split(values)
        base = engine.render(params, light, units.body_of(values))[0]
        truth = _yuv(head, index)
        corner = _coder(head, head.params_at(index))[1]
        bits, _, refresh = coder.code(truth, corner, base=base)
        assert isinstance(refresh, ResidualBox) and bits > 32
        assert residual_gain_db(base, refresh, truth) > 1.0
        take_refresh(engine, units, values, refresh)
        take_refresh(receiver, units, values, refresh)
        assert np.array_equal(engine.reference, receiver.reference)
        (x0, y0), (w, h) = corner, refresh.box
        window = (slice(y0 + 8, y0 + h - 8), slice(x0 + 8, x0 + w - 8))  # inside the feather
        assert box_psnr_db(engine.reference[window], truth[window]) > box_psnr_db(
            base[window], truth[window]
        )
    outside = np.ones(288, bool)
    outside[y0 : y0 + h] = False
    assert np.array_equal(engine.reference[:288][outside], base[:288][outside])


def test_a_zero_residual_leaves_the_rendering_and_a_whole_picture_residual_is_refused(
    head, scene
) -> None:
    from uma.mbc.errors import SceneError
    from uma.mbc.refresh_coder import RESIDUAL_OFFSET, RefreshCoder, ResidualBox, residual_patch

    units, renderer = scene
    base = renderer().render(head.params_at(0))[0]
    flat = ResidualBox((64, 32), (80, 96), np.full((96 * 3 // 2, 80), RESIDUAL_OFFSET, np.uint8))
    patch = residual_patch(base, flat)
    assert np.array_equal(patch[:96], base[32:128, 64:144])
    up = ResidualBox((64, 32), (80, 96), np.full((96 * 3 // 2, 80), 255, np.uint8))
    assert residual_patch(base, up)[:96].min() >= min(255, int(base[32:128, 64:144].min()) + 127)
    half = ResidualBox((64, 32), (80, 96), np.full((48 * 3 // 2, 40), RESIDUAL_OFFSET, np.uint8))
    same = residual_patch(base, half)[:96].astype(int) - base[32:128, 64:144]
    assert np.abs(same).max() <= 1  # the detail finer than the coded size kept
    whole = RefreshCoder((352, 288), (176, 144), 5.0, 14.0, {})
    with pytest.raises(SceneError, match="residual needs a face box"):
        whole.code(base, base=base)
