"""The receiver's whole-scene renderer: identity, ground truth, bad references and light."""

import numpy as np
import pytest

from uma.face.talking_head import Motion, TalkingHeadSource
from uma.mbc.errors import SceneError
from uma.mbc.scene_render import SceneRenderer


@pytest.fixture(scope="module")
def still_head() -> TalkingHeadSource:
    """The talking head without light changes or noise: its frames are pure geometry."""
    motion = Motion(light_gain=0.0, light_angle_rad=0.0, noise_std=0.0)
    return TalkingHeadSource(352, 288, seed=1, motion=motion)


def _psnr(a: np.ndarray, b: np.ndarray) -> float:
    mse = np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2)
    return float(10 * np.log10(255.0**2 / mse))


def test_identity_pose_returns_the_reference(still_head) -> None:
    renderer = SceneRenderer(still_head.description, (352, 288))
    picture, mask = renderer.render(renderer.reference_params)
    assert np.array_equal(picture, renderer.reference)
    assert mask.any()


def test_ground_truth_reproduces_the_whole_frame(still_head) -> None:
    """With the talking head's own far ring the whole frame comes back within 36 dB; with the
    receiver's layered scene (the background stays still and the torso with it, where the
    talking head drags its whole background along) within 21 dB (21.4 measured; 23.9 with the
    stretched scene, which drags the background as the talking head does)."""
    import cv2

    own = SceneRenderer(still_head.description, (352, 288), talking_head_scene=True)
    receiver = SceneRenderer(still_head.description, (352, 288))
    for index in (20, 60):
        frame = cv2.cvtColor(still_head.render_bgr(index), cv2.COLOR_BGR2YUV_I420)
        picture, _ = own.render(still_head.params_at(index))
        assert _psnr(picture[:288], frame[:288]) >= 36.0  # luma, whole picture
        assert _psnr(picture[288:], frame[288:]) >= 44.0  # chroma
        picture, _ = receiver.render(still_head.params_at(index))
        assert _psnr(picture[:288], frame[:288]) >= 21.0


def test_replaced_reference_is_drawn_from(still_head) -> None:
    renderer = SceneRenderer(still_head.description, (352, 288))
    other = np.full_like(renderer.reference, 77)
    renderer.set_reference(other, still_head.params_at(5))
    picture, _ = renderer.render(still_head.params_at(6))
    assert np.all(picture == 77)


def test_bad_reference_and_light_are_typed_errors(still_head) -> None:
    renderer = SceneRenderer(still_head.description, (352, 288))
    params = renderer.reference_params
    with pytest.raises(SceneError, match="176x144|352x288"):
        renderer.set_reference(np.zeros((216, 176), np.uint8), params)
    with pytest.raises(SceneError, match="positive"):
        renderer.set_reference(renderer.reference, np.full_like(params, np.nan))
    with pytest.raises(SceneError, match="gain"):
        renderer.render(params, light=(np.nan, 0.0))
    with pytest.raises(SceneError, match="offset"):
        renderer.render(params, light=(1.0, 1e6))
    picture, mask = renderer.render(params, light=(1.2, -10.0))
    assert picture.dtype == np.uint8 and mask.any()


def test_face_from_the_description_is_relit(still_head) -> None:
    renderer = SceneRenderer(still_head.description, (352, 288))
    renderer.set_face_source(True)
    params = still_head.params_at(10)
    plain, face = renderer.render(params)
    lit, _ = renderer.render(params, light=(1.0, 20.0))
    lifted = lit[:288][face].astype(int) - plain[:288][face]
    assert np.median(lifted) == 20


def test_head_ring_size_is_a_choice_and_the_talking_head_keeps_its_rigid_hair(still_head) -> None:
    """The talking head's hair moves rigidly with its head and its poses are exact: the sender
    picks the head ring that carries hair and ears (1.4 outlines), not the tight one."""
    import cv2

    from uma.mbc.light import choose_head_ring
    from uma.mbc.scene_render import HEAD_RING_CHOICES

    tight = SceneRenderer(still_head.description, (352, 288), head_ring_outlines=1.05)
    wide = SceneRenderer(still_head.description, (352, 288))
    assert not np.allclose(tight.scene.head_ring, wide.scene.head_ring)
    with pytest.raises(SceneError, match="head ring"):
        SceneRenderer(still_head.description, (352, 288), head_ring_outlines=0.9)
    frame0 = cv2.cvtColor(still_head.render_bgr(0), cv2.COLOR_BGR2YUV_I420)
    indices = (60,)
    pictures = [cv2.cvtColor(still_head.render_bgr(i), cv2.COLOR_BGR2YUV_I420) for i in indices]
    poses = [still_head.params_at(i) for i in indices]
    ring = choose_head_ring(
        still_head.description, frame0, still_head.params_at(0), pictures, poses
    )
    assert ring == max(HEAD_RING_CHOICES) == 1.4
    with pytest.raises(SceneError, match="pose each"):
        choose_head_ring(still_head.description, frame0, still_head.params_at(0), pictures, [])


def test_the_light_fades_out_beyond_the_face_without_a_step(still_head, monkeypatch) -> None:
    """A relit face beside a head ring that is not showed a step where the mesh ends (a seam
    across carphone's hair): the light now fades over `LIGHT_FEATHER_OF_FACE` of the face's
    width beyond its edge, and stops there."""
    import cv2

    import uma.mbc.scene_render as scene_render

    renderer = SceneRenderer(still_head.description, (352, 288))
    params = renderer.reference_params
    plain, face = renderer.render(params)
    lit, _ = renderer.render(params, (0.5, 0.0))
    change = plain[:288].astype(int) - lit[:288]
    outside = cv2.distanceTransform((~face).view(np.uint8), cv2.DIST_L2, 3)
    width = np.ptp(np.nonzero(face)[1])
    feather = scene_render.LIGHT_FEATHER_OF_FACE * width
    assert feather >= 3
    assert np.array_equal(change[face], plain[:288][face] - np.rint(plain[:288][face] * 0.5))
    near, far = (outside > 0) & (outside < feather / 2), outside > feather + 1
    assert np.all(change[near] > 0) and not change[far].any()
    # Just outside the face the change is most of the face's own (no step), not none.
    ring = (outside > 0) & (outside <= 1.5)
    assert np.mean(change[ring]) > 0.5 * np.mean(change[face & (outside == 0)])
    monkeypatch.setattr(scene_render, "LIGHT_FEATHER_OF_FACE", 0.0)
    # A new renderer: one that drew this pose keeps the picture (`uma.mbc.render_memo`).
    hard, _ = SceneRenderer(still_head.description, (352, 288)).render(params, (0.5, 0.0))
    assert not (plain[:288].astype(int) - hard[:288])[~face].any()
