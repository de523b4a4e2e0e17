"""The face tracker's settings (`TrackerConfig`) and its Gauss-Newton step (`TRACK_GAUSS_NEWTON`).

Units: correlations (scores), shares (0 to 1) of pixels or vertices, frames, radians. How each
value was chosen, and on which data, is in docs/tracking.md.
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.fit.gauss_newton import GaussNewtonConfig

__all__ = ["TrackerConfig", "TRACK_GAUSS_NEWTON"]

# The tracking step: pose and action units together from the prediction, at most 4
# Levenberg-Marquardt iterations on 2,000 template pixels (of ~17,000 on a CIF face), stopping
# once no vertex moves 0.2 px. Chosen on data the README does not quote (the talking head at
# seed 1, akiyo's and carphone's frames 150-299): against the fitting defaults (8,000 pixels,
# 1e-3 px, 30 iterations; 24 ms a CIF frame, 0.09 px) it costs a fifth of the time for 0.19 px
# median error; against 6 iterations and 0.05 px, 6-7 cost evaluations a frame instead of
# 7-11 (a converged step that cannot lower the error is retried with more damping up to 6
# times: the stop on a small move saves those) at the same error, rate and face PSNR.
TRACK_GAUSS_NEWTON = GaussNewtonConfig(
    iterations=4,
    max_pixels=2000,
    tolerance_px=0.2,
    patch_photometry=True,
    pose_first=False,
)


@dataclass(frozen=True)
class TrackerConfig:
    """Tracking, confidence and re-initialisation settings.

    `lost_below`: a fit correlating below this with the template found no face (a whole face
    covered scores at most 0.22; real faces, tracked with the other starts, at least 0.35).
    `min_inside`: the share of the model's vertices that must lie in the picture.
    `occluded_above`: a tracked fit whose picture departs from the tracked face's appearance
    (`uma.mbc.tracking_gate.AppearanceGate`) in more than this share of its pixels is a covered
    face (uncovered frames at most 0.24, a covered half or more at least 0.69).
    """

    gauss_newton: GaussNewtonConfig = TRACK_GAUSS_NEWTON
    velocity_damping: float = 0.5  # share of the last pose change carried on to the next frame
    lost_below: float = 0.3
    min_inside: float = 0.8
    init_method: str = "hybrid"
    score_pixels: int = 6000  # template pixels the score reads
    # A step that ends below `lost_below` first goes on for this many more iterations (at the
    # fitting's fine tolerance) before the track counts as lost: a fast move (12 px a frame on
    # the CIF talking head) needs 6-8 iterations where a normal frame needs 2-4.
    recover_iterations: int = 12
    # A step ending below `doubt_below` also tries the `other_starts` best of
    # `uma.mbc.tracking_search.starts` around the last good pose, and keeps the best fit.
    doubt_below: float = 0.45
    other_starts: int = 2
    # Both thresholds rise with the track's own level (a running mean of its tracked scores):
    # a step is lost below `lost_of_level` x the level and doubtful below the level minus
    # `doubt_margin`, so a fit 10 px off on a face that usually scores 0.97 is not taken.
    lost_of_level: float = 0.6
    doubt_margin: float = 0.1
    # (pitch, yaw, roll) limits of a tracking step, radians. Roll turns the face within the
    # picture, which the model follows at any angle, so its limit is wider than the turns out
    # of it (0.35 clamped carphone's head for a quarter of its frames: docs/tracking.md).
    rotation_limits_rad: tuple[float, float, float] = (0.45, 0.45, 0.8)
    # After a failed initialisation the tracker holds (steps from the last good pose, a failure
    # that does not re-initialise) for this many frames before it initialises again.
    retry_frames: int = 10
    # A fit whose samples depart from the tracked face's running appearance in more than this
    # share of its pixels has something in front of the face (`uma.mbc.tracking_gate`); after
    # `gate_patience` frames without a face the appearance is forgotten (started again).
    occluded_above: float = 0.4
    gate_patience: int = 25
    # An initialisation (the whole picture searched) is trusted more: refused above this share;
    # accepted, it starts the appearance again (its pose may sit a pixel or two off the
    # track's, and the face may have changed while it was covered).
    occluded_init_above: float = 0.6

    def __post_init__(self) -> None:
        shares = (self.occluded_above, self.occluded_init_above)
        if not all(0.0 < v <= 1.0 for v in shares) or not -1.0 <= self.doubt_below <= 1.0:
            raise ValueError(
                f"tracker: occluded_above and occluded_init_above in (0, 1], doubt_below a "
                f"correlation, got {shares} and {self.doubt_below}"
            )
        if not (0.0 <= self.lost_of_level <= 1.0 and self.doubt_margin >= 0.0):
            raise ValueError(
                f"tracker: lost_of_level in [0, 1] and doubt_margin >= 0 expected, got "
                f"{self.lost_of_level} and {self.doubt_margin}"
            )
        counts = (self.other_starts, self.retry_frames, self.gate_patience)
        if min(counts) < 0 or self.retry_frames < 1 or len(self.rotation_limits_rad) != 3:
            raise ValueError(
                f"tracker: other_starts >= 0, retry_frames >= 1, gate_patience >= 0 and three "
                f"rotation limits expected, got {counts} and {self.rotation_limits_rad}"
            )
        if not 0.0 <= self.velocity_damping <= 1.0:
            raise ValueError(f"tracker: velocity_damping in [0, 1], got {self.velocity_damping}")
        if not -1.0 <= self.lost_below <= 1.0 or not 0.0 < self.min_inside <= 1.0:
            raise ValueError(
                f"tracker: lost_below a correlation and min_inside in (0, 1], got "
                f"{self.lost_below}, {self.min_inside}"
            )
