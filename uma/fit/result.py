"""What a successful fit returns (a failed one returns `uma.failure.Failure`).

Units: parameters as in `uma.face.geometry` (pixels, radians, unitless action units); cost is
1 - correlation (`uma.fit.cost`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FitResult"]


@dataclass(frozen=True, eq=False)
class FitResult:
    """Parameters (6 + A,), the final cost, how many cost evaluations and iterations it took,
    and (when asked for) the best cost after each iteration."""

    params: np.ndarray
    cost: float
    evaluations: int
    iterations: int
    history: tuple[float, ...] = ()

    def __bool__(self) -> bool:
        return True
