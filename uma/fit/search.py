"""Where to search: the box of parameters a fit may visit, and its starting point.

Units: pixels, radians, unitless action units. The face detector's box (or, failing that, the
template's own placement) gives the centre and size; the search may shift the face by a
quarter of its width, scale it by -30 % to +45 % (the detector's box size errs by up to
about 20 % on ORL faces), turn and nod it by up to 0.45 rad (26 deg),
roll it by up to 0.35 rad about a given roll (0, upright, unless the detector found the face
on a turned copy of the image), and move each action unit within [-1, 1.5].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.face.geometry import N_POSE

__all__ = ["SearchBox", "search_box", "ROLL_SEARCH_RAD"]

ROLL_SEARCH_RAD = 0.35  # the roll a search may add to its given roll, either way


@dataclass(frozen=True, eq=False)
class SearchBox:
    low: np.ndarray
    high: np.ndarray
    face_width_px: float

    def clip(self, params: np.ndarray) -> np.ndarray:
        # np.clip's values (low <= high), without its Python wrapper: SAABs clips every step
        return np.minimum(np.maximum(params, self.low), self.high)

    def contains(self, params: np.ndarray) -> bool:
        return bool(np.all(params >= self.low - 1e-9) and np.all(params <= self.high + 1e-9))

    @property
    def bounds(self) -> list[tuple[float, float]]:
        return list(zip(self.low.tolist(), self.high.tolist(), strict=True))


def search_box(
    start: np.ndarray, face_width_px: float, *, shift: float = 0.25, roll_rad: float = 0.0
) -> SearchBox:
    """The search box around `start` (6 + A,) for a face `face_width_px` wide, its roll within
    ROLL_SEARCH_RAD of `roll_rad`."""
    n_actions = start.size - N_POSE
    low = np.concatenate(
        [
            [
                start[0] - shift * face_width_px,
                start[1] - shift * face_width_px,
                0.7 * start[2],
                -0.45,
                -0.45,
                roll_rad - ROLL_SEARCH_RAD,
            ],
            np.full(n_actions, -1.0),
        ]
    )
    high = np.concatenate(
        [
            [
                start[0] + shift * face_width_px,
                start[1] + shift * face_width_px,
                1.45 * start[2],
                0.45,
                0.45,
                roll_rad + ROLL_SEARCH_RAD,
            ],
            np.full(n_actions, 1.5),
        ]
    )
    return SearchBox(low=low, high=high, face_width_px=float(face_width_px))
