"""The layered scene: plate, torso, head; no ghost of the old head, identity, bad input."""

import numpy as np
import pytest

from uma.face.talking_head import Motion, TalkingHeadSource
from uma.mbc.errors import SceneError
from uma.mbc.layers import N_BODY, NO_BODY_MOTION, Plate, body_problem, fill_unknown
from uma.mbc.scene_render import HALO_OF_HEAD, SceneRenderer

SIZE = (352, 288)


@pytest.fixture(scope="module")
def description():
    motion = Motion(light_gain=0.0, light_angle_rad=0.0, noise_std=0.0)
    return TalkingHeadSource(*SIZE, seed=1, motion=motion).description


def _background(seed: int = 4) -> np.ndarray:
    """A textured YUV 4:2:0 background (smooth noise, colour too)."""
    import cv2

    rng = np.random.default_rng(seed)
    width, height = SIZE
    noise = rng.uniform(40, 200, (height * 3 // 2, width)).astype(np.float32)
    return np.clip(cv2.GaussianBlur(noise, (0, 0), 3.0) * 2 - 120, 0, 255).astype(np.uint8)


def _pose(description, x: float, y: float, scale_of: float = 0.45) -> np.ndarray:
    params = np.asarray(description.params, dtype=np.float64).copy()
    params[0], params[1] = x, y
    params[2] *= scale_of  # a small person: two of them side by side leave background between
    return params


def _scene(renderer: SceneRenderer, background: np.ndarray, params, body=None) -> np.ndarray:
    """The synthetic truth: `background` with a flat bright person (head, halo, torso as the
    renderer cuts it at `params`, the torso moved by `body`) on it."""
    return _scene_and_person(renderer, background, params, body)[0]


def _scene_and_person(renderer, background, params, body=None):
    import cv2

    from uma.mbc.layers import body_matrix, cut_person

    width, height = SIZE
    points = renderer.scene.points(params)
    head, halo, torso, anchor = cut_person(renderer.scene, points, SIZE, HALO_OF_HEAD)
    if body is not None:
        torso = cv2.warpAffine(torso, body_matrix(body, anchor), SIZE, flags=cv2.INTER_NEAREST)
    person = (head | halo | torso) > 0
    out = background.copy()
    out[:height][person] = 230
    return out, person


def test_identity_pose_and_no_body_motion_return_the_reference(description) -> None:
    renderer = SceneRenderer(description, SIZE)
    assert renderer.layered
    picture, _ = renderer.render(renderer.reference_params, None, NO_BODY_MOTION)
    assert np.array_equal(picture, renderer.reference)
    reference = _scene(renderer, _background(), _pose(description, 176, 120))
    renderer.set_reference(reference, _pose(description, 176, 120))
    picture, _ = renderer.render(_pose(description, 176, 120), None, np.zeros(N_BODY))
    assert np.array_equal(picture, reference)


def test_a_moving_person_leaves_no_ghost(description) -> None:
    """The person stood on the left (the plate learns the right), then on the right (the
    reference); rendered in the middle, the background the person uncovers on the right is
    the true background (>= 40 dB; 100 measured: exact), where the stretched scene shows the
    old person there (< 15 dB)."""
    background = _background()
    renderer = SceneRenderer(description, SIZE)
    left, right, middle = (_pose(description, x, 110) for x in (60, 250, 170))
    was_left = _scene_and_person(renderer, background, left)
    renderer.set_reference(was_left[0], left)
    reference, was_right = _scene_and_person(renderer, background, right)
    renderer.set_reference(reference, right)
    body = np.array([-80.0, 0.0, 0.0])  # the torso from the right to the middle
    truth, person = _scene_and_person(renderer, background, middle)
    picture, _ = renderer.render(middle, None, body)
    height = SIZE[1]
    uncovered = was_right & ~person & ~was_left[1]  # seen on the left reference
    assert uncovered.sum() > 2000
    error = picture[:height][uncovered].astype(float) - truth[:height][uncovered]
    psnr = 10 * np.log10(255.0**2 / max(np.mean(error**2), 1e-10))
    assert psnr >= 40.0
    # The person itself is where it should be.
    assert np.mean(picture[:height][person] == 230) > 0.9
    stretched = SceneRenderer(description, SIZE, layered=False)
    stretched.set_reference(reference, right)
    ghost, _ = stretched.render(middle)
    error = ghost[:height][uncovered].astype(float) - truth[:height][uncovered]
    assert 10 * np.log10(255.0**2 / np.mean(error**2)) < 15.0


@pytest.mark.parametrize(
    "body",
    [
        [np.nan, 0.0, 0.0],
        [1000.0, 0.0, 0.0],
        [0.0, 0.0, 2.0],
        [0.0, 0.0],
    ],
)
def test_absurd_body_motion_is_refused(description, body) -> None:
    renderer = SceneRenderer(description, SIZE)
    assert body_problem(body, SIZE)
    with pytest.raises(SceneError, match="body motion"):
        renderer.render(renderer.reference_params, None, np.array(body))


def test_a_refresh_of_another_scene_restarts_the_plate_and_a_lost_plate_shows_the_reference(
    description,
) -> None:
    renderer = SceneRenderer(description, SIZE)
    pose = _pose(description, 176, 120)
    renderer.set_reference(_scene(renderer, _background(4), pose), pose)
    other = _scene(renderer, np.full_like(_background(), 20), pose)  # a dark room
    renderer.set_reference(other, pose)
    assert "started again" in renderer.plate.reason
    renderer.plate.forget()
    assert renderer.plate.reason == "plate lost"
    picture, _ = renderer.render(pose)
    assert np.array_equal(picture, other)  # the last good picture, not grey or NaN


def test_fill_keeps_known_pixels_and_fills_the_rest_from_them() -> None:
    plane = np.full((40, 60), 90, np.uint8)
    plane[:, 30:] = 170
    known = np.ones_like(plane, bool)
    known[10:30, 20:40] = False
    plane[~known] = 0
    filled = fill_unknown(plane, known)
    assert np.array_equal(filled[known], plane[known])
    assert 90 <= filled[20, 22] <= 170 and 90 <= filled[20, 38] <= 170
    assert filled[20, 22] < filled[20, 38]
    assert np.all(fill_unknown(plane, np.zeros_like(known)) == 128)


def test_plate_refuses_a_picture_of_another_size() -> None:
    plate = Plate((32, 16))
    with pytest.raises(SceneError, match="plate"):
        plate.update(np.zeros((30, 32), np.uint8), np.zeros((16, 32), bool))


def test_the_fill_continues_an_edge_into_the_band_next_to_known_background() -> None:
    """A wall (90) over a floor (170), a diagonal person hiding the right: the unknown pixels
    next to the floor stay floor, not an average of wall and floor (the dotted line along a
    moved torso's outline)."""
    plane = np.full((60, 80), 90, np.uint8)
    plane[30:] = 170
    ys, xs = np.mgrid[0:60, 0:80]
    known = xs < 20 + ys  # the person: right of a diagonal
    plane[~known] = 0
    filled = fill_unknown(plane, known)
    assert np.array_equal(filled[known], plane[known])
    band = ~known & (xs < 22 + ys)  # within 2 px of the known floor and wall
    # Measured: within 3 and 18 levels (the smooth fill alone: 3 and 33).
    assert np.all(np.abs(filled[band & (ys > 34)].astype(int) - 170) <= 6)
    assert np.all(np.abs(filled[band & (ys < 26)].astype(int) - 90) <= 22)
    # The chroma planes' fill, the nearest known pixel: exact here.
    nearest = fill_unknown(plane, known, "nearest")
    assert np.array_equal(nearest[known], plane[known])
    assert np.all(nearest[band & (ys > 34)] == 170) and np.all(nearest[band & (ys < 26)] == 90)
