"""The camera's motion: measured by the engine, coded beside the body's, moving the plate."""

import numpy as np
import pytest

from uma.mbc import FaceUnits, PacketError, ParameterDecoder, ParameterEncoder, StreamConfig
from uma.mbc.body import BodyTracker
from uma.mbc.layers import N_BODY, N_TORSO, shift_yuv
from uma.mbc.scene_render import SceneRenderer

SIZE = (352, 288)


def _units(head, camera: bool = True) -> FaceUnits:
    return FaceUnits.of(head.model, head.description.params, light=True, body=True, camera=camera)


def _frame(head) -> np.ndarray:
    """The talking head's first frame on a textured background (smooth noise)."""
    import cv2

    frame = cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420)
    renderer = SceneRenderer(head.description, SIZE)
    renderer.set_reference(frame, head.params_at(0))
    noise = np.random.default_rng(4).uniform(40, 200, frame.shape).astype(np.float32)
    texture = np.clip(cv2.GaussianBlur(noise, (0, 0), 3.0) * 2 - 120, 0, 255).astype(np.uint8)
    outside = ~renderer.person_mask
    frame[:288][outside] = texture[:288][outside]
    return frame


def test_a_shifted_scene_is_a_camera_motion_and_a_still_one_none(head) -> None:
    """The whole reference shifted 6 px right and 4 px down: the camera moved by that; the
    reference itself (and a shift under `HOLD_PX`) is no camera motion, exactly zero."""
    frame = _frame(head)
    renderer = SceneRenderer(head.description, SIZE)
    renderer.set_reference(frame, head.params_at(0))
    tracker = BodyTracker(camera=True)
    shifted = shift_yuv(frame, np.array([[1.0, 0, 6], [0, 1.0, 4]]), 1)[:288]
    body = tracker.measure(renderer, shifted)
    assert isinstance(body, np.ndarray) and body.shape == (N_BODY,)
    assert np.allclose(body[N_TORSO:], (6.0, 4.0), atol=0.5)
    still = tracker.measure(renderer, frame[:288])
    assert np.array_equal(still[N_TORSO:], (0.0, 0.0))
    nudged = shift_yuv(frame, np.array([[1.0, 0, 0.3], [0, 1.0, 0.2]]), 1)[:288]
    assert np.array_equal(tracker.measure(renderer, nudged)[N_TORSO:], (0.0, 0.0))
    assert BodyTracker().measure(renderer, shifted).shape == (N_TORSO,)  # off: the torso alone


def test_stream_round_trips_camera_motion_and_refuses_an_absurd_one(
    head, stream_round_trip
) -> None:
    units, config = _units(head), StreamConfig()
    sent = {
        frame: np.concatenate(
            [head.params_at(frame), (1.0, -1.0, 0.01, 4.0 * np.sin(frame / 3), -2.5), (1.0, 0.0)]
        )
        for frame in range(10)
    }
    packets, got, half = stream_round_trip(units, sent)
    assert all(p.camera and p.body for p in packets)
    assert sorted(got) == list(range(10))
    for frame, values in got.items():
        assert np.all(np.abs(values - sent[frame]) <= half)
        assert units.body_of(values).shape == (N_BODY,)
    with pytest.raises(PacketError, match="camera motion present"):
        ParameterDecoder(_units(head, camera=False)).decode(packets[0].to_bytes())
    absurd = ParameterEncoder(units, config)
    values = np.concatenate([head.params_at(0), (0, 0, 0, 3000.0, 0), (1.0, 0.0)])
    fresh = ParameterDecoder(units, config)
    with pytest.raises(PacketError, match="camera motion: shift"):
        fresh.decode((absurd.push(0, values) + absurd.flush())[0].to_bytes())


def test_the_plate_moves_with_the_camera_and_a_refresh_meets_it(head) -> None:
    """Rendered with a camera motion, the background away from the person is the plate
    shifted; a new reference taken at that motion moves the plate first, so the old plate
    and the new picture agree (no restart)."""
    frame = _frame(head)
    renderer = SceneRenderer(head.description, SIZE)
    renderer.set_reference(frame, head.params_at(0))
    matrix = np.array([[1.0, 0, 5], [0, 1.0, -3]])
    body = np.array([0.0, 0.0, 0.0, 5.0, -3.0])
    picture, _ = renderer.render(head.params_at(0), None, body)
    truth = shift_yuv(renderer.plate.picture, matrix, 1)
    import cv2

    person = cv2.dilate(renderer.person_mask.view(np.uint8), np.ones((9, 9), np.uint8)) > 0
    away = ~person
    away[:8], away[-8:], away[:, :8], away[:, -8:] = False, False, False, False
    assert np.array_equal(picture[:288][away], truth[:288][away])
    moved = shift_yuv(frame, matrix, 1)
    renderer.set_reference(moved, head.params_at(0), camera=(5.0, -3.0))
    assert renderer.plate.reason == ""
