"""Face animation units: how the codec measures pose and action units, like MPEG-4 FBA's FAPUs.

Units: each parameter is counted in its own unit of the personal model, so one quantiser step
means the same on any face and any picture size. As in MPEG-4 (ISO/IEC 14496-2, FAPU):
- translations (tx_px, ty_px) in ES/1024, ES the eye separation (pupils 3.5-3.6) of the
  neutral personal model, in pixels at the description's scale;
- scale (scale_px) in 1/1024 of the description's scale;
- rotations in the angle unit AU = 1e-5 rad;
- an action unit in 1/1024 of the face distance it acts on (MNS mouth-nose for the mouth,
  MW mouth width for the lip stretch, ENS eye-nose for brows and eyelids), per unit of
  movement of its most moved vertex: a value of 1024 moves that vertex by one whole distance.

mbcdata's `uma.face.fap` maps `.fap` files onto the model; this module is the codec's own
measure (no `fap_units` existed when it was written) and uses the same FAPU definitions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.errors import FaceError
from uma.face.geometry import N_POSE
from uma.face.model import FaceModel

__all__ = ["FaceUnits", "ANGLE_UNIT_RAD", "action_fapu"]

ANGLE_UNIT_RAD = 1e-5
FAPU_DIVISOR = 1024.0

# Which neutral face distance each of uma's action units is measured against; others use MNS.
_ACTION_FAPU = {
    "lip_stretch": "MW",
    "brow_raise": "ENS",
    "eye_close": "ENS",
}


def _distance(model: FaceModel, a: str, b: str, axis: int | None = None) -> float:
    fp = model.feature_points
    if a not in fp or b not in fp:
        raise FaceError(f"{model.name}: feature points {a} and {b} are needed for the FAPUs")
    delta = model.vertices[fp[a]] - model.vertices[fp[b]]
    return float(abs(delta[axis]) if axis is not None else np.linalg.norm(delta[:2]))


def action_fapu(name: str) -> str:
    """The FAPU an action unit is measured in."""
    return _ACTION_FAPU.get(name, "MNS")


@dataclass(frozen=True, eq=False)
class FaceUnits:
    """Per parameter, the size of one unit in the geometry's own units (px, rad, coefficient)."""

    unit: np.ndarray  # (6 + A,)
    names: tuple[str, ...]
    distances: dict[str, float]  # ES, ENS, MNS, MW in model units

    @classmethod
    def of(cls, model: FaceModel, params: np.ndarray) -> FaceUnits:
        """Units of `model` placed by `params` (the description's pose: its scale_px)."""
        params = np.asarray(params, dtype=np.float64)
        if params.shape != (N_POSE + model.n_actions,) or not params[2] > 0:
            raise FaceError(
                f"{model.name}: expected {N_POSE + model.n_actions} parameters with a positive "
                f"scale, got {params.shape}"
            )
        eyes_y = 0.5 * (
            model.vertices[model.feature_points.get("3.5", 0), 1]
            + model.vertices[model.feature_points.get("3.6", 0), 1]
        )
        distances = {
            "ES": _distance(model, "3.5", "3.6"),
            "MNS": _distance(model, "9.15", "2.2", axis=1),
            "MW": _distance(model, "8.3", "8.4"),
        }
        distances["ENS"] = float(abs(eyes_y - model.vertices[model.feature_points["9.15"], 1]))
        if min(distances.values()) <= 1e-6:
            raise FaceError(f"{model.name}: a face distance for the FAPUs is zero: {distances}")
        scale = float(params[2])
        unit = [
            distances["ES"] * scale / FAPU_DIVISOR,
            distances["ES"] * scale / FAPU_DIVISOR,
            scale / FAPU_DIVISOR,
            ANGLE_UNIT_RAD,
            ANGLE_UNIT_RAD,
            ANGLE_UNIT_RAD,
        ]
        for name, displacement in zip(model.action_unit_names, model.action_units, strict=True):
            moved = float(np.linalg.norm(displacement, axis=1).max())
            if moved <= 0:
                raise FaceError(f"{model.name}: action unit {name} moves no vertex")
            unit.append(distances[action_fapu(name)] / FAPU_DIVISOR / moved)
        names = (
            "tx_px",
            "ty_px",
            "scale_px",
            "rx_rad",
            "ry_rad",
            "rz_rad",
            *model.action_unit_names,
        )
        return cls(unit=np.array(unit), names=names, distances=distances)

    def to_units(self, params: np.ndarray) -> np.ndarray:
        """Parameters (..., 6 + A) in face animation units."""
        return np.asarray(params, dtype=np.float64) / self.unit

    def from_units(self, values: np.ndarray) -> np.ndarray:
        """Face animation units back to the geometry's parameters."""
        return np.asarray(values, dtype=np.float64) * self.unit
