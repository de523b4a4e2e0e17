"""The tracker's local search: where a tracking step may go, and the other starts it tries.

Units: parameters as in `uma.face.geometry` (pixels, radians, action units); scores are
correlations (1 - the illumination-compensated fitting cost) over the template's pixels.

A tracking step starts from the predicted pose. When it ends doubtful (its score below
`TrackerConfig.doubt_below`), `starts` gives the other places to start from before the track
counts as lost: the last good pose itself (the prediction may have overshot), the same pose
rolled either way and turned back towards the camera (a fast turn or roll is where a single
start slides into a wrong minimum: rotation traded for translation and scale), and shifted by
a tenth of the face's width. `Scorer` scores them all in one batch on the step's crop, so only
the best few are refined.
"""

from __future__ import annotations

import numpy as np

from uma.face.geometry import N_POSE
from uma.fit.cost import Cost, FitTemplate
from uma.fit.search import SearchBox

__all__ = ["Scorer", "starts", "tracking_box"]


def tracking_box(
    start: np.ndarray, face_width_px: float, rotation_limits_rad: tuple[float, float, float]
) -> SearchBox:
    """The box a tracking step stays in: a quarter face width of shift, -30 % to +45 % of
    scale around `start`, rotations (pitch, yaw, roll) within +-`rotation_limits_rad`, action
    units within [-1, 1.5], as `uma.fit.search.search_box` but for the rotation limits (a
    tracked head may roll further than an initialisation looks for)."""
    pitch, yaw, roll = rotation_limits_rad
    n_actions = start.size - N_POSE
    shift = 0.25 * face_width_px
    low = np.concatenate(
        [[start[0] - shift, start[1] - shift, 0.7 * start[2], -pitch, -yaw, -roll],
         np.full(n_actions, -1.0)]
    )  # fmt: skip
    high = np.concatenate(
        [[start[0] + shift, start[1] + shift, 1.45 * start[2], pitch, yaw, roll],
         np.full(n_actions, 1.5)]
    )  # fmt: skip
    return SearchBox(low=low, high=high, face_width_px=float(face_width_px))


def starts(last_good: np.ndarray, face_width_px: float) -> np.ndarray:
    """Other starts (S, P) around `last_good`: itself, rolled +-0.15 rad, turned and nodded
    halfway back to the camera, its action units neutral, and shifted by a tenth of the face
    width in x and y (each alone)."""
    base = np.asarray(last_good, dtype=np.float64)
    out = [base.copy()]
    for roll in (-0.15, 0.15):
        moved = base.copy()
        moved[5] += roll
        out.append(moved)
    frontal = base.copy()
    frontal[3:5] *= 0.5
    out.append(frontal)
    neutral = base.copy()
    neutral[N_POSE:] = 0.0
    out.append(neutral)
    step = 0.1 * face_width_px
    for axis in (0, 1):
        for sign in (-1.0, 1.0):
            moved = base.copy()
            moved[axis] += sign * step
            out.append(moved)
    return np.array(out)


class Scorer:
    """Scores of candidates on one picture's crop: `scores(params)` takes parameters in the
    whole picture's pixels; `offset` is what the crop's corner subtracts from tx and ty.

    `evaluations` counts calls, not candidates: one batch is one pass of the scoring kernel,
    far cheaper per candidate than a Gauss-Newton evaluation (the unit the engine's modelled
    compute prices)."""

    def __init__(self, template: FitTemplate, crop: np.ndarray, offset: np.ndarray, pixels: int):
        self.cost = Cost(template, crop, illumination=True).thinned(pixels)
        self.offset = offset
        self.evaluations = 0

    def scores(self, params: np.ndarray) -> np.ndarray:
        """(B,) scores of (B, P) candidates, or a 0-d score of one (P,)."""
        self.evaluations += 1
        return 1.0 - self.cost(np.asarray(params, dtype=np.float64) - self.offset)
