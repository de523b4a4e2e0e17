"""The tracker on the talking head: follows the ground truth, re-initialises when lost."""

from __future__ import annotations

import numpy as np

from uma.fit.mde import mde_px
from uma.mbc.encoder import FaceTracker, TrackFailure


def test_tracker_follows_the_talking_head(head, head_frames) -> None:
    tracker = FaceTracker(head.description, rng=0)
    errors = []
    for index, picture in enumerate(head_frames):
        result = tracker.track(picture)
        assert result, result
        assert result.frame == index
        assert result.reinitialised == (index == 0)
        assert result.reason == ("first picture" if index == 0 else "tracked")
        assert result.evaluations > 0 and np.all(np.isfinite(result.params))
        errors.append(mde_px(head.model, result.params, head.params_at(index)))
    assert np.median(errors) < 0.5 and max(errors) < 1.0, errors


def test_a_lost_track_reinitialises_and_says_why(head, head_frames) -> None:
    tracker = FaceTracker(head.description, rng=0)
    for picture in head_frames[:3]:
        assert tracker.track(picture)
    # The face jumps 70 px to the right: too far for a tracking step.
    jumped = np.roll(head_frames[3], 70, axis=1)
    result = tracker.track(jumped)
    assert result.reinitialised
    assert result.reason.startswith("track lost") or not result


def test_a_flat_picture_is_a_failure_value(head, head_frames) -> None:
    tracker = FaceTracker(head.description, rng=0)
    assert tracker.track(head_frames[0])
    result = tracker.track(np.full((288, 352), 90, np.uint8))
    assert isinstance(result, TrackFailure) and not result
    assert "flat" in result.reason
    # The next good picture initialises again.
    again = tracker.track(head_frames[2])
    assert again and again.reinitialised


def test_a_face_leaving_the_picture_reinitialises_and_says_so(head, head_frames) -> None:
    tracker = FaceTracker(head.description, rng=0)
    reasons = []
    for k in range(16):
        # The head slides right 12 px a frame (300 px/s) until it leaves the picture.
        picture = np.full_like(head_frames[0], 100)
        shift = 12 * k
        picture[:, shift:] = head_frames[0][:, : picture.shape[1] - shift]
        result = tracker.track(picture)
        reasons.append(result.reason)
        assert result or k >= 13, result.reason
    assert reasons[0] == "first picture"
    assert reasons[1:13] == ["tracked"] * 12  # a fast move, but followed
    assert all("face leaving the picture" in r for r in reasons[13:]), reasons[13:]
