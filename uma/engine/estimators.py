"""Bandwidth estimators by name (`engine.estimator.kind`): each folds a receiver report into the
engine's `EstimatorState` with the signature of `uma.engine.estimator.update_estimate`."""

from __future__ import annotations

from collections.abc import Callable

from uma.engine.estimator import EstimatorState, update_estimate
from uma.engine.webrtc import remb_update

__all__ = ["ESTIMATORS", "EstimatorUpdate"]

EstimatorUpdate = Callable[..., EstimatorState]

ESTIMATORS: dict[str, EstimatorUpdate] = {"uma": update_estimate, "webrtc": remb_update}
