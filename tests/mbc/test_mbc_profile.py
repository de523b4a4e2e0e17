"""One rendering for the bench and the simulation: both build the receiver's renderer from the
`engine.mbc` profile (`uma.mbc.profile`), the outline's softening included."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from uma.config.codecs import MbcConfig
from uma.face import TalkingHeadSource
from uma.mbc.profile import profile_renderer

SIZE = (176, 144)


@pytest.fixture(scope="module")
def description():
    return TalkingHeadSource(*SIZE, seed=0).description


def _moved(description) -> np.ndarray:
    params = np.array(description.params, dtype=np.float64)
    params[0] += 6.0  # the head 6 px right of the reference: the outline band is 3 px wide
    return params


def test_the_description_s_ring_and_the_profile_s_softening(description):
    tight = replace(description, head_ring_outlines=1.05)
    soft = profile_renderer(tight, SIZE, MbcConfig(soften_outline=True))
    hard = profile_renderer(tight, SIZE, MbcConfig(soften_outline=False))
    assert soft.soft_outline and not hard.soft_outline
    assert np.array_equal(soft.scene.head_ring, hard.scene.head_ring)
    params = _moved(description)
    assert not np.array_equal(soft.render(params)[0], hard.render(params)[0])
    # No ring described: the profile's (the wide one), never softened (exact poses).
    plain = profile_renderer(description, SIZE, MbcConfig(soften_outline=True))
    assert not plain.soft_outline
    assert not np.array_equal(plain.scene.head_ring, soft.scene.head_ring)
    wide = profile_renderer(description, SIZE, MbcConfig(head_ring_outlines=1.8))
    assert not np.array_equal(wide.scene.head_ring, plain.scene.head_ring)


def test_the_ring_travels_in_the_description_file(description, tmp_path):
    from uma.face import load_description

    path = tmp_path / "d.face"
    plain_bytes = description.save(path)
    assert load_description(path).head_ring_outlines is None
    assert replace(description, head_ring_outlines=1.05).save(path) > plain_bytes
    assert load_description(path).head_ring_outlines == 1.05


@pytest.mark.parametrize("soften", [False, True])
def test_the_bench_draws_what_the_simulation_draws(description, soften):
    from uma.bench.mbc import _renderer
    from uma.bench.mbc_clips import ClipSpec
    from uma.sim.mbc_codecs import scene_renderer

    profile = MbcConfig(soften_outline=soften)
    description = replace(description, head_ring_outlines=1.05)
    clip = ClipSpec("head", [np.zeros((SIZE[1] * 3 // 2, SIZE[0]), np.uint8)], 25.0, description)
    bench = _renderer(clip, "description", None, SIZE, profile)
    world = scene_renderer(description, SIZE, profile)
    params = _moved(description)
    assert np.array_equal(bench.render(params)[0], world.render(params)[0])
    # Without a section the world renders as the section's defaults, as the bench does.
    default = _renderer(clip, "description", None, SIZE, MbcConfig())
    assert np.array_equal(
        default.render(params)[0], scene_renderer(description, SIZE).render(params)[0]
    )


def test_the_sender_chooses_the_tight_ring_on_a_real_face_and_keeps_the_wide_one_on_exact_poses(
    shared_data,
):
    import cv2

    from uma.mbc.profile import describe_clip_with_ring, with_sender_ring
    from uma.paths import codecs_dir

    akiyo = describe_clip_with_ring(codecs_dir() / "face" / "akiyo.yaml")
    assert akiyo.head_ring_outlines == 1.05
    source = TalkingHeadSource(*SIZE, seed=0)
    frames = [cv2.cvtColor(source.render_bgr(i), cv2.COLOR_BGR2YUV_I420) for i in range(26)]
    assert with_sender_ring(source.description, frames).head_ring_outlines == 1.4
