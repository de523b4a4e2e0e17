"""A failed fit or detection as a value: it tests false and carries the reason.

Fitting and detection return either their result or a `Failure` (as scikit-image's
`from_estimate` does), so callers write `if not fit: log(fit.reason)` and never see NaN
parameters or an exception from inside numpy.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Failure"]


@dataclass(frozen=True)
class Failure:
    """Why a fit or detection did not succeed; `bool(failure)` is False."""

    reason: str

    def __bool__(self) -> bool:
        return False

    def __str__(self) -> str:
        return self.reason
