"""The tracker holds a face through large motion: a bow (pitch with the head dropping), a
turn toward profile and a roll (the head tilted toward a shoulder), as the talking head
performs them (ground truth known)."""

from __future__ import annotations

import numpy as np
import pytest

from uma.face.talking_head import Motion, TalkingHeadSource
from uma.fit.mde import mde_px
from uma.mbc.encoder import FaceTracker

FRAMES = 36


class _Scripted(TalkingHeadSource):
    """The talking head (no sway, still speaking and blinking) moved by `script(t)`: added
    (dx_px, dy_px, pitch, yaw, roll) at t from 0 to 1 over the clip."""

    def __init__(self, script) -> None:
        quiet = Motion(yaw_rad=0, pitch_rad=0, roll_rad=0, shift_frac=0, scale_frac=0)
        super().__init__(352, 288, seed=5, motion=quiet)
        self.script = script

    def params_at(self, index: int) -> np.ndarray:
        params = super().params_at(index)
        dx, dy, pitch, yaw, roll = self.script(min(index / (FRAMES - 1), 1.0))
        params[0] += dx
        params[1] += dy
        params[3] += pitch
        params[4] += yaw
        params[5] += roll
        return params


def _ramp(t: float) -> float:
    """Down and back up: 0 -> 1 -> 0 (a bow or a turn that comes back)."""
    return float(np.sin(np.pi * t) ** 2)


SCRIPTS = {
    # A bow: the head nods 0.35 rad forward and drops 18 px (turning about the neck).
    "bow": lambda t: (0.0, 18.0 * _ramp(t), 0.35 * _ramp(t), 0.0, 0.0),
    # A turn: 0.42 rad toward profile and 10 px sideways.
    "turn": lambda t: (-10.0 * _ramp(t), 0.0, 0.0, 0.42 * _ramp(t), 0.0),
    # A roll: the head tilted 0.7 rad (40 degrees; carphone's reaches 0.54) and 8 px sideways.
    "roll": lambda t: (8.0 * _ramp(t), 0.0, 0.0, 0.0, 0.7 * _ramp(t)),
}


@pytest.mark.parametrize("kind", sorted(SCRIPTS))
def test_tracking_holds_a_bow_a_turn_and_a_roll(kind) -> None:
    import cv2

    source = _Scripted(SCRIPTS[kind])
    tracker = FaceTracker(source.description, rng=0)
    rng = np.random.default_rng(2)
    errors, reinits = [], 0
    for index in range(FRAMES):
        picture = cv2.cvtColor(source.render_bgr(index, rng=rng), cv2.COLOR_BGR2GRAY)
        result = tracker.track(picture, frame=index)
        assert result, f"{kind} frame {index}: {result.reason}"
        reinits += index > 0 and result.reinitialised
        errors.append(mde_px(source.model, result.params, source.params_at(index)))
    assert reinits == 0
    # Measured: bow median 0.36 px, at most 0.51; turn 0.21, at most 0.38; roll 0.23, 0.35.
    assert np.median(errors) < 0.6 and max(errors) < 1.2, np.round(errors, 2)


@pytest.mark.parametrize("roll", [0.4, 0.55, -0.55])
def test_a_head_already_tilted_is_found_on_the_first_picture(roll) -> None:
    """The upright face detector finds the talking head rolled by 0.4 rad, whose fit then
    stopped at the upright search's 0.35 (2.0 px off), and misses it rolled by 0.55 (no face
    at all); the initialisation searches past the edge, and looks on turned copies of the
    picture (0.04 px on the first picture)."""
    import cv2

    source = _Scripted(lambda t: (0.0, 0.0, 0.0, 0.0, roll))
    tracker = FaceTracker(source.description, rng=0)
    rng = np.random.default_rng(2)
    for index in range(3):
        picture = cv2.cvtColor(source.render_bgr(index, rng=rng), cv2.COLOR_BGR2GRAY)
        result = tracker.track(picture, frame=index)
        assert result, f"frame {index}: {result.reason}"
        assert mde_px(source.model, result.params, source.params_at(index)) < 0.3
    assert abs(result.params[5] - source.params_at(2)[5]) < 0.05
