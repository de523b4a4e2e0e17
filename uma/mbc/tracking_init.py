"""Where the tracker's automatic initialisation looks for the face, in turn.

Units: parameters as in `uma.face.geometry` (pixels, radians, action units). First the face
detector's upright box (or, when the description's own picture held no detectable face, where
the description was cut out); a fit whose roll stops at that search's edge is searched again
past it (a head tilted further that the detector still found upright). Failing that, around
the last good pose, its roll searched about that pose's. Failing that, the detector on turned
copies of the picture (`uma.fit.fit.turned_guess`: OpenCV's cascade finds upright faces only).
Failing that, the detector on the picture at its own size, for a face too small for the
scaled search (`uma.fit.fit.small_guess`: a wide shot).
Each step is a `uma.fit.fit_face` with the tracker's method; a failure tests false and names
every place looked.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.failure import Failure
from uma.fit.cost import FitTemplate
from uma.fit.fit import (
    DETECTOR_ROLLS_RAD,
    DetectorCalibration,
    fit_face,
    small_guess,
    turned_guess,
)
from uma.fit.search import ROLL_SEARCH_RAD, search_box

__all__ = ["InitSearch"]


@dataclass(frozen=True, eq=False)
class InitSearch:
    """The initialisation's search for `template` (the personal model on its description)."""

    template: FitTemplate
    method: str
    calibration: DetectorCalibration | None  # the detector's box on the description, if any
    home: np.ndarray  # where the description was cut out (pose parameters)

    def fit(self, image: np.ndarray, why: str, last_good: np.ndarray | None, rng):
        """(fit or failure, detector runs, `why` with how the face was found) on `image`."""
        start = box = None
        if self.calibration is None:
            start, box = self.home, search_box(self.home, self.template.face_width_px)
        fit = fit_face(self.template, image, method=self.method, start=start, box=box,
                       calibration=self.calibration, rng=rng)  # fmt: skip
        detections = int(self.calibration is not None)
        if fit and abs(fit.params[5]) > ROLL_SEARCH_RAD - 0.01:
            fit, why = self._past_roll(image, fit, why, rng)
        if not fit and last_good is not None and start is None:
            fit, why = self._around(image, fit, why, last_good, rng)
        if not fit and self.calibration is not None:
            fit, detections, why = self._turned(image, fit, detections, why, rng)
        if not fit and self.calibration is not None:
            fit, detections, why = self._small(image, fit, detections, why, rng)
        return fit, detections, why

    def _width(self, params: np.ndarray) -> float:
        return float(self.template.face_width_px * params[2] / self.template.params[2])

    def _past_roll(self, image: np.ndarray, fit, why: str, rng):
        """The fit searched again about the first turn beyond its roll, from it; the better."""
        roll = float(np.copysign(DETECTOR_ROLLS_RAD[0], fit.params[5]))
        box = search_box(fit.params, self._width(fit.params), roll_rad=roll)
        again = fit_face(self.template, image, method=self.method, start=fit.params, box=box,
                         rng=rng)  # fmt: skip
        if again and again.cost < fit.cost:
            return again, f"{why} (its roll searched past {ROLL_SEARCH_RAD} rad)"
        return fit, why

    def _around(self, image: np.ndarray, failed: Failure, why: str, last: np.ndarray, rng):
        """Around the last good pose, where the detector found nothing."""
        box = search_box(last, self._width(last), roll_rad=float(last[5]))
        retry = fit_face(self.template, image, method=self.method, start=last, box=box, rng=rng)
        if retry:
            return retry, f"{why} ({failed.reason}: searched around the last pose)"
        return Failure(f"{failed.reason}; around the last pose: {retry.reason}"), why

    def _turned(self, image: np.ndarray, failed: Failure, detections: int, why: str, rng):
        """The detector on turned copies of `image`, and the fit from what it finds."""
        guess = turned_guess(self.template, image, self.calibration)
        if not guess:
            reason = f"{failed.reason}; {guess.reason}"
            return Failure(reason), detections + len(DETECTOR_ROLLS_RAD), why
        start, box = guess
        detections += DETECTOR_ROLLS_RAD.index(start[5]) + 1
        fit = fit_face(self.template, image, method=self.method, start=start, box=box, rng=rng)
        if not fit:
            reason = f"{failed.reason}; found turned by {start[5]:.1f} rad: {fit.reason}"
            return Failure(reason), detections, why
        return fit, detections, f"{why} (found on the picture turned by {start[5]:.1f} rad)"

    def _small(self, image: np.ndarray, failed: Failure, detections: int, why: str, rng):
        """The detector on `image` at its own size, for a face too small for the scaled search
        (a wide shot), and the fit from what it finds."""
        guess = small_guess(self.template, image, self.calibration)
        if not guess:
            return Failure(f"{failed.reason}; {guess.reason}"), detections + 1, why
        start, box = guess
        fit = fit_face(self.template, image, method=self.method, start=start, box=box, rng=rng)
        if not fit:
            return (
                Failure(f"{failed.reason}; a small face found: {fit.reason}"),
                detections + 1,
                why,
            )
        return fit, detections + 1, f"{why} (a small face, found at the picture's own size)"
