"""The person's cut kept by content equals the cut computed afresh, for every input."""

from __future__ import annotations

import numpy as np
import pytest

from uma.face.talking_head import Motion, TalkingHeadSource
from uma.mbc.cut_memo import CutMemo
from uma.mbc.layers import cut_person
from uma.mbc.scene_render import HALO_OF_HEAD, SceneRenderer

SIZE = (176, 144)


@pytest.fixture(scope="module")
def description():
    motion = Motion(light_gain=0.0, light_angle_rad=0.0, noise_std=0.0)
    return TalkingHeadSource(*SIZE, seed=2, motion=motion).description


def _same(one, other) -> bool:
    return all(np.array_equal(a, b) and a.dtype == b.dtype for a, b in zip(one, other, strict=True))


def test_a_kept_cut_is_the_plain_cut_and_a_changed_input_is_cut_again(description) -> None:
    memo = CutMemo(cut_person, entries=2)
    scene = SceneRenderer(description, SIZE).scene
    points = scene.points(np.asarray(description.params, dtype=np.float64))
    first = memo.cut(scene, points, SIZE, HALO_OF_HEAD)
    first[0][:] = 7  # a caller writing into what it got changes nothing kept
    again = memo.cut(scene, points.copy(), SIZE, HALO_OF_HEAD)
    assert memo.hits == 1
    assert _same(again, cut_person(scene, points, SIZE, HALO_OF_HEAD))
    moved = points.copy()
    moved[:, 0] += 0.25  # a quarter pixel to the right
    assert _same(memo.cut(scene, moved, SIZE, HALO_OF_HEAD),
                 cut_person(scene, moved, SIZE, HALO_OF_HEAD))  # fmt: skip
    assert _same(memo.cut(scene, points, SIZE, 0.3), cut_person(scene, points, SIZE, 0.3))
    assert memo.hits == 1
