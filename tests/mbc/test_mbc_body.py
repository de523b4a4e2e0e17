"""The torso's motion: measured by the engine, coded beside the face, checked at the receiver."""

import numpy as np
import pytest

from uma.mbc import FaceUnits, PacketError, ParameterDecoder, ParameterEncoder
from uma.mbc.body import BodyTracker
from uma.mbc.scene_render import SceneRenderer


def _units(head, body: bool = True) -> FaceUnits:
    return FaceUnits.of(head.model, head.description.params, light=True, body=body)


def test_stream_round_trips_body_motion_within_half_a_step(head, stream_round_trip) -> None:
    units = _units(head)
    sent = {
        frame: np.concatenate(
            [
                head.params_at(frame),
                (3.0 * np.sin(frame / 3), -2.0 * frame / 11, 0.02 * np.cos(frame / 4)),
                (1.1, -3.0),
            ]
        )
        for frame in range(12)
    }
    packets, got, half = stream_round_trip(units, sent)
    assert all(p.body and p.light for p in packets)
    assert sorted(got) == list(range(12))
    for frame, values in got.items():
        assert np.all(np.abs(values - sent[frame]) <= half)
        geometry, light = units.split(values)
        assert geometry.shape == head.params_at(0).shape and light is not None
        assert units.body_of(values).shape == (3,)


def test_absurd_body_motion_and_a_flag_mismatch_are_packet_errors(head) -> None:
    units = _units(head)
    encoder, decoder = ParameterEncoder(units), ParameterDecoder(units)
    params = np.concatenate([head.params_at(0), (0.0, 0.0, 3.0), (1.0, 0.0)])  # 3 rad
    packets = encoder.push(0, params) + encoder.flush()
    with pytest.raises(PacketError, match="rotation"):
        decoder.decode(packets[0].to_bytes())
    assert decoder.params is None
    plain = ParameterDecoder(_units(head, body=False))
    with pytest.raises(PacketError, match="body motion present"):
        plain.decode(packets[0].to_bytes())


def test_body_tracker_measures_a_shifted_torso(head) -> None:
    """The reference itself shifted 6 px right and 4 px down: the torso moved by that."""
    import cv2

    frame = cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420)
    renderer = SceneRenderer(head.description, (352, 288))
    renderer.set_reference(frame, head.params_at(0))
    shifted = cv2.warpAffine(
        frame[:288], np.float32([[1, 0, 6], [0, 1, 4]]), (352, 288), borderMode=cv2.BORDER_REFLECT
    )
    tracker = BodyTracker()
    body = tracker.measure(renderer, shifted)
    assert isinstance(body, np.ndarray)
    assert np.allclose(body[:2], (6.0, 4.0), atol=1.0) and abs(body[2]) < 0.02
    assert np.allclose(tracker.measure(renderer, frame[:288])[:2], 0.0, atol=0.5)
    # A new reference (the shifted picture itself): measured against it, no motion.
    moved = frame.copy()
    moved[:288] = shifted
    renderer.set_reference(moved, head.params_at(0))
    assert np.allclose(tracker.measure(renderer, shifted)[:2], 0.0, atol=0.5)
    plain = SceneRenderer(head.description, (352, 288), layered=False)
    failure = tracker.measure(plain, frame[:288])
    assert not failure and "no layers" in failure.reason


def test_a_still_torso_keeps_its_motion_without_aligning_again(head, monkeypatch) -> None:
    """The same picture again (plus noise under `STILL_LEVELS`): the last motion stands and
    ECC is not run; a picture shifted 6 px is aligned again."""
    import cv2

    import uma.mbc.body as body_module

    frame = cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420)
    renderer = SceneRenderer(head.description, (352, 288))
    renderer.set_reference(frame, head.params_at(0))
    shifted = cv2.warpAffine(
        frame[:288], np.float32([[1, 0, 6], [0, 1, 4]]), (352, 288), borderMode=cv2.BORDER_REFLECT
    )
    tracker = BodyTracker()
    first = tracker.measure(renderer, shifted).copy()
    calls = []
    real = cv2.findTransformECC
    monkeypatch.setattr(cv2, "findTransformECC", lambda *a: calls.append(1) or real(*a))
    noisy = np.clip(shifted.astype(int) + np.random.default_rng(0).integers(0, 2, shifted.shape),
                    0, 255).astype(np.uint8)  # fmt: skip
    assert np.array_equal(tracker.measure(renderer, noisy), first) and not calls
    assert body_module.STILL_LEVELS > 0.5  # that noise is below it
    assert np.allclose(tracker.measure(renderer, frame[:288])[:2], 0.0, atol=0.5) and calls


def test_the_torso_rows_align_as_the_whole_template_does(head, monkeypatch) -> None:
    """The template cut to the torso's rows (and `TEMPLATE_MARGIN_ROWS`) gives the motion
    the whole picture's template gives, within a hundredth of a pixel; it holds fewer rows."""
    import cv2

    import uma.mbc.body as body_module

    frame = cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420)
    renderer = SceneRenderer(head.description, (352, 288))
    renderer.set_reference(frame, head.params_at(0))
    matrix = cv2.getRotationMatrix2D((176.0, 250.0), 1.5, 1.0)
    matrix[:, 2] += (5.0, 3.0)
    moved = cv2.warpAffine(frame[:288], matrix, (352, 288), borderMode=cv2.BORDER_REFLECT)
    cut = BodyTracker()
    rows = cut.measure(renderer, moved)
    assert cut._rows[1].shape[0] < 144
    monkeypatch.setattr(body_module, "TEMPLATE_MARGIN_ROWS", 10_000)  # every row: the old way
    whole_tracker = BodyTracker()
    whole = whole_tracker.measure(renderer, moved)
    assert (
        whole_tracker._rows == (0, whole_tracker._rows[1])
        and whole_tracker._rows[1].shape[0] == 144
    )
    assert isinstance(rows, np.ndarray) and isinstance(whole, np.ndarray)
    assert np.allclose(rows[:2], whole[:2], atol=0.01) and abs(rows[2] - whole[2]) < 1e-4
    assert abs(rows[0] - 5.0) < 1.5 and abs(rows[2]) > 0.01  # it did move and turn
