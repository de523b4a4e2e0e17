"""The tracker while the face is covered: a failure value with its reason, held rather than
re-initialised every frame, and the face found again by tracking once it shows."""

from __future__ import annotations

import numpy as np
import pytest

from uma.face.geometry import project
from uma.mbc.encoder import FaceTracker, TrackerConfig, TrackFailure
from uma.mbc.tracking_gate import AppearanceGate
from uma.mbc.tracking_search import starts, tracking_box


def _face_box(head, index: int) -> tuple[slice, slice]:
    points = project(head.model, head.params_at(index))
    (x0, y0), (x1, y1) = points.min(axis=0).astype(int) - 2, points.max(axis=0).astype(int) + 2
    return slice(y0, y1), slice(x0, x1)


def _covered(picture: np.ndarray, rows: slice, cols: slice, kind: str) -> np.ndarray:
    out = picture.copy()
    if kind == "flat":
        out[rows, cols] = 150
    else:  # something textured that is not this face: the picture's own corner
        h, w = out[rows, cols].shape
        out[rows, cols] = picture[:h, :w]
    return out


@pytest.mark.parametrize("kind", ["flat", "texture"])
def test_a_covered_face_is_held_not_drawn(head, head_frames, kind) -> None:
    tracker = FaceTracker(head.description, rng=0)
    for index in range(5):
        assert tracker.track(head_frames[index], frame=index)
    rows, cols = _face_box(head, 4)
    held = [
        tracker.track(_covered(head_frames[5], rows, cols, kind), frame=5 + k) for k in range(6)
    ]
    assert all(isinstance(r, TrackFailure) and not r for r in held), [r.reason for r in held]
    # One initialisation is tried when the face goes; then the last good picture is held.
    assert sum(r.reinitialised for r in held) <= 1, [r.reason for r in held]
    assert all("held the last good picture" in r.reason for r in held[1:]), held[1].reason
    # The face shows again where it was: tracked from the last good pose, no initialisation.
    back = tracker.track(head_frames[5], frame=11)
    assert back and not back.reinitialised, back.reason
    assert back.reason.startswith("tracked (found again")


def test_a_half_covered_face_is_a_failure_not_a_pose(head, head_frames) -> None:
    tracker = FaceTracker(head.description, rng=0)
    for index in range(5):
        assert tracker.track(head_frames[index], frame=index)
    rows, cols = _face_box(head, 4)
    lower = slice((rows.start + rows.stop) // 2, rows.stop)
    result = tracker.track(_covered(head_frames[5], lower, cols, "flat"), frame=5)
    assert not result and "covered" in result.reason, result.reason


def test_a_wider_gate_lets_the_covered_face_through(head, head_frames) -> None:
    """The gate alone makes the difference above: without it the half-covered face is tracked."""
    tracker = FaceTracker(
        head.description, config=TrackerConfig(occluded_above=1.0, occluded_init_above=1.0), rng=0
    )
    for index in range(5):
        assert tracker.track(head_frames[index], frame=index)
    rows, cols = _face_box(head, 4)
    lower = slice((rows.start + rows.stop) // 2, rows.stop)
    assert tracker.track(_covered(head_frames[5], lower, cols, "flat"), frame=5)


def test_no_face_at_all_retries_initialisation_only_every_few_frames(head, head_frames) -> None:
    tracker = FaceTracker(head.description, config=TrackerConfig(retry_frames=4), rng=0)
    empty = np.flipud(head_frames[0]) // 4 + 60  # upside down and faint: no face to find
    results = [tracker.track(empty, frame=k) for k in range(9)]
    assert not any(results)
    tried = [k for k, r in enumerate(results) if r.reinitialised]
    assert tried == [0, 4, 8], [r.reason for r in results]
    # reset() forgets the wait: the next picture initialises at once.
    tracker.reset()
    assert tracker.track(head_frames[0], frame=9).reinitialised


def test_the_gate_tells_the_tracked_face_from_a_covered_one(head, head_frames) -> None:
    gate = AppearanceGate(FaceTracker(head.description, rng=0).template)
    for index in range(6):
        gate.accept(np.float32(head_frames[index]), head.params_at(index))
    params = head.params_at(6)
    assert gate.outlier_share(np.float32(head_frames[6]), params) < 0.1
    rows, cols = _face_box(head, 6)
    covered = _covered(head_frames[6], rows, cols, "flat")
    assert gate.outlier_share(np.float32(covered), params) > 0.5
    gate.reset()
    assert gate.outlier_share(np.float32(covered), params) == 0.0  # nothing learnt yet


def test_other_starts_surround_the_last_pose() -> None:
    last = np.array([100.0, 80.0, 50.0, 0.1, -0.2, 0.05, 0.3, -0.1])
    out = starts(last, 40.0)
    assert out.shape == (9, 8)
    assert np.array_equal(out[0], last)
    assert sorted(np.round(out[1:3, 5] - last[5], 6)) == [-0.15, 0.15]
    assert np.allclose(out[3, 3:5], 0.5 * last[3:5]) and np.all(out[4, 6:] == 0)
    shifts = out[5:, :2] - last[:2]
    assert sorted(np.abs(shifts).max(axis=1)) == [4.0] * 4
    box = tracking_box(last, 40.0, (0.5, 0.6, 0.7))
    assert box.high[3:6].tolist() == [0.5, 0.6, 0.7] and box.low[5] == -0.7
    assert box.low[0] == 90.0 and box.high[1] == 90.0


def test_a_face_that_leaves_and_comes_back_is_found_again(head, head_frames) -> None:
    tracker = FaceTracker(head.description, config=TrackerConfig(retry_frames=4), rng=0)
    width = head_frames[0].shape[1]
    # Out to the right at 24 px a frame, 6 frames off the picture, then back the same way.
    shifts = [24 * k for k in range(12)] + [width] * 6 + [24 * k for k in range(11, -1, -1)]
    results = []
    noise = np.random.default_rng(0).normal(100, 12, head_frames[0].shape)
    for frame, shift in enumerate(shifts):
        picture = np.clip(noise, 0, 255).astype(np.uint8)  # a background, not a flat picture
        picture[:, shift:] = head_frames[0][:, : width - shift]
        results.append(tracker.track(picture, frame=frame))
    gone = [r for r, s in zip(results, shifts, strict=True) if s == width]
    assert not any(gone) and all(r.reason for r in gone)
    # Initialisation is tried at most once every 4 frames while the face is away.
    tried = [k for k, r in enumerate(results) if r.reinitialised and not r]
    assert all(b - a >= 4 for a, b in zip(tried, tried[1:], strict=False)), tried
    # Back in the picture: found again (within the wait) and tracked to the end.
    assert all(results[-3:]), [r.reason for r in results[-3:]]
    moved = project(head.model, results[-1].params) - project(head.model, head.params_at(0))
    distance = np.linalg.norm(moved, axis=1)
    assert np.median(distance) < 2.0 and distance.max() < 8.0, distance.max()
