"""The renderer's memo: a picture asked for again at its reference is the one drawn, as a copy,
and a new reference or face source forgets it."""

import cv2
import numpy as np

from uma.mbc.render_memo import MEMO_PICTURES, RenderMemo
from uma.mbc.scene_render import SceneRenderer


def _renderer(head) -> SceneRenderer:
    renderer = SceneRenderer(head.description, (352, 288))
    renderer.set_reference(cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420),
                           head.params_at(0))  # fmt: skip
    return renderer


def test_a_picture_asked_again_is_the_one_drawn_and_a_copy(head) -> None:
    renderer, params, body = _renderer(head), head.params_at(7), np.array([2.0, 1.0, 0.0])
    first, face = renderer.render(params, (1.05, 2.0), body)
    kept = first.copy()
    first[:] = 0  # a caller drawing on its picture leaves the memo's alone
    again, again_face = renderer.render(params, (1.05, 2.0), body)
    assert renderer._memo.hits == 1
    assert np.array_equal(again, kept) and np.array_equal(again_face, face)
    fresh = _renderer(head).render(params, (1.05, 2.0), body)[0]  # drawn, not remembered
    assert np.array_equal(again, fresh)
    renderer.render(params, (1.05, 2.5), body)  # other light: drawn
    renderer.render(params, (1.05, 2.0), body, luma_only=True)  # a judge's: never kept
    assert renderer._memo.hits == 1


def test_a_new_reference_or_face_source_forgets_what_was_drawn(head) -> None:
    renderer, params = _renderer(head), head.params_at(7)
    before = renderer.render(params)[0]
    renderer.set_reference(before, params)
    after = renderer.render(params)[0]
    assert renderer._memo.hits == 0
    renderer.set_face_source(True)
    renderer.render(params)
    assert renderer._memo.hits == 0
    assert after.shape == before.shape


def test_the_memo_keeps_the_newest_pictures_only() -> None:
    memo, face = RenderMemo(), np.zeros((2, 2), bool)
    for k in range(MEMO_PICTURES + 1):
        memo.put(np.array([float(k)]), None, None, np.full((3, 2), k, np.uint8), face)
    assert memo.get(np.array([0.0]), None, None) is None
    assert memo.get(np.array([float(MEMO_PICTURES)]), None, None)[0][0, 0] == MEMO_PICTURES
    assert memo.get(np.array([1.0]), (1.0, 0.0), None) is None  # light is in the key
