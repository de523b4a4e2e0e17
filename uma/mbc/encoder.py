"""The MBC encoder's analysis: initialise the personal model on a picture, then track it.

Units: parameters as in `uma.face.geometry` (pixels, radians, action units); scores are
correlations (1 - the fitting cost, illumination-compensated, over the template's pixels);
work is counted in cost evaluations (and detector runs), never in wall-clock time, so the
engine can model compute time.

The first picture, and every re-initialisation, runs the project's best automatic
initialisation (`uma.fit.fit_face`, the hybrid: detector, SAABs in two views, Gauss-Newton
polish), looking where `uma.mbc.tracking_init` says: the detector's upright box, around the
last good pose, turned copies of the picture (a head tilted toward a shoulder), the picture at
its own size (a small face in a wide shot).
Later pictures are tracked: Gauss-Newton (with a gain and offset per triangle patch) from the
previous parameters moved on by a damped constant-velocity prediction of the pose; a
step that ends doubtful also starts from a few poses around the last good one
(`uma.mbc.tracking_search`) and keeps the best. A fit is trusted when it scores at least
`lost_below` and the appearance gate (`uma.mbc.tracking_gate`) finds no large part of the face
unlike the tracked face (a hand in front). An untrusted fit, or a predicted face leaving the
picture, re-initialises; when that finds no face either, the tracker holds: for
`retry_frames` frames it gives a `TrackFailure` that did not re-initialise (the display keeps
the last good picture), steps from the last good pose each frame, and takes the face back by
tracking when it shows again there, or by the next initialisation. Every failure is a
`TrackFailure` (a `uma.failure.Failure`: it tests false and carries the reason), never NaN and
never a pose drawn where the face is not. Settings and their measurements: `TrackerConfig`,
docs/tracking.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from uma.face.describe import ContentDescription
from uma.face.geometry import N_POSE, project
from uma.failure import Failure
from uma.fit.cost import FitTemplate
from uma.fit.fit import DetectorCalibration, check_image, detect
from uma.fit.gauss_newton import GaussNewtonConfig, gauss_newton
from uma.mbc.tracking_config import TRACK_GAUSS_NEWTON, TrackerConfig
from uma.mbc.tracking_gate import AppearanceGate
from uma.mbc.tracking_init import InitSearch
from uma.mbc.tracking_search import Scorer, starts, tracking_box

__all__ = ["TrackerConfig", "TrackResult", "TrackFailure", "FaceTracker", "TRACK_GAUSS_NEWTON"]


@dataclass(frozen=True, eq=False)
class TrackResult:
    """One picture's parameters and how they were found."""

    frame: int
    params: np.ndarray
    score: float
    reinitialised: bool
    reason: str  # "tracked", or why it (re-)initialised
    evaluations: int
    detections: int = 0  # face detector runs

    def __bool__(self) -> bool:
        return True


@dataclass(frozen=True)
class TrackFailure(Failure):
    """No parameters for this picture: the reason, and the work spent finding none."""

    frame: int = -1
    evaluations: int = 0
    detections: int = 0
    reinitialised: bool = True
    score: float = field(default=float("nan"), compare=False)


class FaceTracker:
    """Tracks the personal model of `description` through a sequence of gray pictures."""

    def __init__(
        self,
        description: ContentDescription,
        *,
        config: TrackerConfig | None = None,
        rng=None,
    ):
        self.description = description
        self.config = config = config if config is not None else TrackerConfig()
        self.rng = np.random.default_rng(rng)
        self.template = FitTemplate.build(description.model, description.gray, description.params)
        self.n_params = self.template.params.size
        # The tracking step's pixels, thinned once (Gauss-Newton would thin on every call).
        step = -(-self.template.raster.size // config.gauss_newton.max_pixels)
        self._step_template = self.template.subsampled(step)
        self.gate = AppearanceGate(self.template)
        self.last_share = float("nan")  # the gate's share on the last fit it judged
        self._level: float | None = None  # running mean of the tracked scores
        box = detect(self.template.image)
        calibration = DetectorCalibration.from_template(self.template, box) if box else None
        # Without a calibration, initialisation starts where the description was cut out.
        home = self.template.params.copy()
        home[:2] += np.asarray(description.origin_px, dtype=np.float64)
        self.search = InitSearch(self.template, config.init_method, calibration, home)
        self._previous: np.ndarray | None = None
        self._before: np.ndarray | None = None
        self._last_good: np.ndarray | None = None  # kept across resets
        self._held = 0  # frames without a trustworthy pose since the last good one
        self._next_init: int | None = None  # after a failed initialisation: when to try again
        self._frame = 0

    def reset(self) -> None:
        """Forget the track and the face's tracked appearance: the next picture initialises."""
        self._forget()
        self.gate.reset()
        self._level = None

    def _forget(self) -> None:
        self._previous = self._before = None
        self._held, self._next_init = 0, None

    def _inside(self, params: np.ndarray, shape: tuple[int, int], points=None) -> float:
        """The share of the model's vertices at `params` (projected: `points`) in the picture."""
        points = project(self.template.model, params) if points is None else points
        ok = (
            (points[:, 0] >= 0)
            & (points[:, 0] <= shape[1] - 1)
            & (points[:, 1] >= 0)
            & (points[:, 1] <= shape[0] - 1)
        )
        return float(ok.mean())

    def _thresholds(self) -> tuple[float, float]:
        """(lost, doubtful) scores for a tracking step: the settings, raised with the level."""
        c, level = self.config, self._level
        if level is None:
            return c.lost_below, c.doubt_below
        return max(c.lost_below, c.lost_of_level * level), max(
            c.doubt_below, level - c.doubt_margin
        )

    def step(
        self,
        image: np.ndarray,
        prediction: np.ndarray,
        last_good: np.ndarray | None = None,
        thresholds: tuple[float, float] | None = None,
        *,
        points: np.ndarray | None = None,
    ):
        """One tracking step from `prediction`: (fit, score, evaluations). A step scoring below
        the doubtful score also starts from the best `other_starts` of the starts around
        `last_good` (`uma.mbc.tracking_search.starts`); one still below the lost score goes on for
        `recover_iterations` more before it is given up.

        Gauss-Newton sees only the picture around the predicted face (a margin of 0.4 face
        widths, beyond the 0.25 its search box allows): its blur and gradients then cost a
        third of a CIF frame's. Translation is additive, so the crop only shifts tx and ty.
        `points`: the prediction's projection (`project`), when the caller has it.
        """
        config = self.config
        lost, doubt = thresholds or (config.lost_below, config.doubt_below)
        width = self.template.face_width_px * prediction[2] / self.template.params[2]
        points = project(self.template.model, prediction) if points is None else points
        x0, y0, x1, y1 = _crop_box(points, 0.4 * width + 8.0, image.shape)
        crop = image[y0:y1, x0:x1]
        offset = np.zeros_like(prediction)
        offset[:2] = (x0, y0)
        scorer = Scorer(self.template, crop, offset, config.score_pixels)

        def run(start: np.ndarray, gn: GaussNewtonConfig):
            local = start - offset
            box = tracking_box(local, width, config.rotation_limits_rad)
            fit = gauss_newton(self.template, crop, local, box, config=gn, scored=False)
            params = fit.params + offset
            ok = bool(np.all(np.isfinite(params)))
            return params, (float(scorer.scores(params)) if ok else -1.0), fit.evaluations, ok

        params, score, evaluations, ok = run(prediction, config.gauss_newton)
        if score < doubt and last_good is not None and config.other_starts > 0:
            candidates = starts(last_good, width)
            order = np.argsort(-scorer.scores(candidates))[: config.other_starts]
            for start in candidates[order]:
                other, other_score, more, other_ok = run(start, config.gauss_newton)
                evaluations += more
                if other_ok and other_score > score:
                    params, score, ok = other, other_score, True
        if score < lost and config.recover_iterations > 0:
            longer = replace(
                config.gauss_newton,
                iterations=config.recover_iterations,
                tolerance_px=min(config.gauss_newton.tolerance_px, 0.05),
            )
            params, score, more, ok = run(params if ok else prediction, longer)
            evaluations += more
        return params, score, evaluations + scorer.evaluations

    def track(self, picture: np.ndarray, *, frame: int | None = None) -> TrackResult | TrackFailure:
        """Parameters for the next picture (gray, (H, W)); `frame` defaults to a running count."""
        frame = self._frame if frame is None else int(frame)
        self._frame = frame + 1
        problem = check_image(np.asarray(picture))
        if problem is not None:
            self.reset()
            return TrackFailure(
                f"frame {frame}: {problem.reason}", frame=frame, reinitialised=False
            )
        image = np.asarray(picture, dtype=np.float32)
        if self._previous is None:
            if self._next_init is not None and frame < self._next_init:
                return TrackFailure(
                    f"frame {frame}: no face (initialising again at frame {self._next_init})",
                    frame=frame,
                    reinitialised=False,
                )
            result = self._initialise(image, frame, "first picture" if frame == 0 else "no track")
            if not result:
                self._next_init = frame + self.config.retry_frames
            return result
        prediction = self._previous.copy()
        if self._before is not None:
            velocity = self._previous[:N_POSE] - self._before[:N_POSE]
            prediction[:N_POSE] += self.config.velocity_damping * velocity
        points = project(self.template.model, prediction)  # once: the share inside, the crop
        inside = self._inside(prediction, image.shape, points)
        if inside < self.config.min_inside:
            why = f"face leaving the picture ({100 * inside:.0f} % inside)"
            return self._lost(image, frame, why, spent=0, score=float("nan"))
        lost, doubt = self._thresholds()
        params, score, evaluations = self.step(
            image, prediction, self._previous, (lost, doubt), points=points
        )
        if score < lost:
            why = f"track lost (score {score:.2f} < {lost:.2f})"
            return self._lost(image, frame, why, spent=evaluations, score=score)
        covered = self._covered(image, params, self.config.occluded_above)
        if covered:
            return self._lost(image, frame, covered, spent=evaluations, score=score)
        self.gate.accept(image, params)
        self._level = score if self._level is None else 0.9 * self._level + 0.1 * score
        reason = "tracked"
        if self._held:
            reason = f"tracked (found again after {self._held} frames without a face)"
        self._held, self._next_init = 0, None
        self._before, self._previous = self._previous, params
        self._last_good = params
        return TrackResult(frame, params, score, False, reason, evaluations)

    def _covered(self, image: np.ndarray, params: np.ndarray, limit: float) -> str:
        """Why the face at `params` is taken for covered (a share above `limit`), or ""."""
        if self._held >= self.config.gate_patience:
            self.gate.reset()  # the face changed for good (light, a turn): learn it again
        share = self.gate.outlier_share(image, params)
        self.last_share = share
        if share <= limit:
            return ""
        return f"face covered ({100 * share:.0f} % of it unlike the tracked face)"

    def _lost(
        self, image: np.ndarray, frame: int, why: str, *, spent: int, score: float
    ) -> TrackResult | TrackFailure:
        """No trustworthy pose from the track: initialise again, unless an initialisation
        failed less than `retry_frames` ago; then hold (a failure that did not re-initialise:
        the display keeps the last good picture) and step from the last good pose next time."""
        self._held += 1
        self._before = None  # no velocity across a gap
        if self._next_init is not None and frame < self._next_init:
            return TrackFailure(
                f"frame {frame}: {why}; held the last good picture ({self._held} frames without "
                f"a face; initialising again at frame {self._next_init})",
                frame=frame,
                evaluations=spent,
                reinitialised=False,
                score=score,
            )
        last, held = self._previous, self._held
        result = self._initialise(image, frame, why, spent=spent)
        if not result:
            self._previous, self._held = last, held
            self._next_init = frame + self.config.retry_frames
        return result

    def _initialise(
        self, image: np.ndarray, frame: int, why: str, *, spent: int = 0
    ) -> TrackResult | TrackFailure:
        self._forget()
        fit, detections, why = self.search.fit(image, why, self._last_good, self.rng)
        if not fit:
            return TrackFailure(
                f"frame {frame}: {why}; initialisation failed: {fit.reason}",
                frame=frame,
                evaluations=spent,
                detections=detections,
            )
        score = 1.0 - fit.cost
        evaluations = spent + fit.evaluations
        problem = self._refused(image, fit.params, score)
        if problem:
            return TrackFailure(
                f"frame {frame}: {why}; {problem}",
                frame=frame,
                evaluations=evaluations,
                detections=detections,
                score=score,
            )
        self.gate.reset()
        self.gate.accept(image, fit.params)
        if self._level is None:
            self._level = score  # the first initialisation's match sets the level to keep
        self._previous = fit.params
        self._held, self._next_init = 0, None
        self._last_good = fit.params
        return TrackResult(frame, fit.params, score, True, why, evaluations, detections)

    def _refused(self, image: np.ndarray, params: np.ndarray, score: float) -> str:
        """Why an initialisation's fit at `params` scoring `score` is not taken, or ""."""
        if score < self.config.lost_below:
            return f"initialisation matched poorly (score {score:.2f} < {self.config.lost_below})"
        inside = self._inside(params, image.shape)
        if inside < self.config.min_inside:
            return f"initialisation found a face only {100 * inside:.0f} % inside the picture"
        covered = self._covered(image, params, self.config.occluded_init_above)
        return f"initialisation found a {covered}" if covered else ""


def _crop_box(points: np.ndarray, margin: float, shape: tuple[int, int]) -> tuple[int, ...]:
    """(x0, y0, x1, y1): the box about `points` (N, 2) `margin` px wider, in a picture of
    `shape` (H, W)."""
    height_px, width_px = shape
    x0 = int(max(0, np.floor(points[:, 0].min() - margin)))
    y0 = int(max(0, np.floor(points[:, 1].min() - margin)))
    x1 = int(min(width_px, np.ceil(points[:, 0].max() + margin) + 1))
    y1 = int(min(height_px, np.ceil(points[:, 1].max() + margin) + 1))
    return x0, y0, x1, y1
