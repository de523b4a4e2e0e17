"""Face animation units: how the codec measures pose and action units, like MPEG-4 FBA's FAPUs.

Units: each parameter is counted in its own unit of the personal model, so one quantiser step
means the same on any face and any picture size. As in MPEG-4 (ISO/IEC 14496-2, FAPU):
- translations (tx_px, ty_px) in ES/1024, ES the eye separation (pupils 3.5-3.6) of the
  neutral personal model, in pixels at the description's scale;
- scale (scale_px) in 1/1024 of the description's scale;
- rotations in the angle unit AU = 1e-5 rad;
- an action unit in 1/1024 of the face distance it acts on (MNS mouth-nose for the mouth,
  MW mouth width for the lip stretch, ENS eye-nose for the brows, IRISD for the eyelids), per
  unit of movement of its most moved vertex: a value of 1024 moves that vertex by one whole
  distance.

The distances are `uma.face.fap_map.fap_units` of the personal model (the `.fap` reader's), so the
codec and `.fap` files measure a face alike.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.errors import FaceError
from uma.face.geometry import N_POSE
from uma.face.model import FaceModel

__all__ = [
    "FaceUnits",
    "ANGLE_UNIT_RAD",
    "action_fapu",
    "LIGHT_NAMES",
    "LIGHT_UNITS",
    "BODY_KINDS",
    "CAMERA_KINDS",
]

ANGLE_UNIT_RAD = 1e-5
# Light on the face against the receiver's reference: a luma gain in 1/1024 and an offset in
# 1/16 of a level (`uma.mbc.scene_render`).
LIGHT_NAMES = ("light_gain", "light_offset_levels")
LIGHT_UNITS = (1.0 / 1024.0, 1.0 / 16.0)
LIGHT_KINDS = ("LIGHT_GAIN", "LIGHT_OFFSET")
FAPU_DIVISOR = 1024.0
# The torso's motion (`uma.mbc.layers.BODY_NAMES`): shifts in ES/1024 like the head's, rotation
# in AU.
BODY_KINDS = ("BODY_SHIFT", "BODY_SHIFT", "BODY_ROTATION")
# The camera's motion (`uma.mbc.layers.CAMERA_NAMES`, the plate's shift): in ES/1024.
CAMERA_KINDS = ("CAMERA_SHIFT", "CAMERA_SHIFT")

# Which neutral face distance each of uma's action units is measured against; others use MNS.
_ACTION_FAPU = {
    "lip_stretch": "MW",
    "brow_raise": "ENS",
    "eye_close": "IRISD",
}


def action_fapu(name: str) -> str:
    """The FAPU an action unit is measured in."""
    return _ACTION_FAPU.get(name, "MNS")


# The pose parameters every set begins with, before the model's action units.
POSE_NAMES = ("tx_px", "ty_px", "scale_px", "rx_rad", "ry_rad", "rz_rad")


@dataclass(frozen=True, eq=False)
class FaceUnits:
    """Per parameter, the size of one unit in the geometry's own units (px, rad, coefficient)."""

    unit: np.ndarray  # (6 + A,)
    names: tuple[str, ...]
    distances: dict[str, float]  # ES, ENS, MNS, MW, IRISD in model units
    kinds: tuple[str, ...] = ()  # per action unit, the distance it is measured in (then light)
    light: bool = False  # the last two parameters are the light (`LIGHT_NAMES`)
    body: bool = False  # three parameters before the light: the torso's motion (`BODY_KINDS`)
    camera: bool = False  # with `body`, two more after it: the camera's motion (`CAMERA_KINDS`)
    origin: np.ndarray | None = None  # subtracted before scaling (a gain travels as gain - 1)

    @classmethod
    def of(
        cls,
        model: FaceModel,
        params: np.ndarray,
        *,
        light: bool = False,
        body: bool = False,
        camera: bool = False,
    ) -> FaceUnits:
        """Units of `model` placed by `params` (the description's pose: its scale_px); with
        `body` three more parameters, the torso's motion, then with `camera` (only with
        `body`) two more, the camera's, and with `light` two more, the face's
        light, end every set (in that order)."""
        params = np.asarray(params, dtype=np.float64)
        if params.shape != (N_POSE + model.n_actions,) or not params[2] > 0:
            raise FaceError(
                f"{model.name}: expected {N_POSE + model.n_actions} parameters with a positive "
                f"scale, got {params.shape}"
            )
        distances = _distances(model)
        scale = float(params[2])
        unit = _geometry_units(model, distances, scale)
        names = (*POSE_NAMES, *model.action_unit_names)
        kinds = tuple(action_fapu(name) for name in model.action_unit_names)
        if body:
            from uma.mbc.layers import CAMERA_NAMES, TORSO_NAMES

            shift = distances["ES"] * scale / FAPU_DIVISOR
            unit += [shift, shift, ANGLE_UNIT_RAD]
            names += TORSO_NAMES
            kinds += BODY_KINDS
        camera = bool(camera) and body
        if camera:
            unit += [shift, shift]
            names += CAMERA_NAMES
            kinds += CAMERA_KINDS
        if light:
            unit += LIGHT_UNITS
            names += LIGHT_NAMES
            kinds += LIGHT_KINDS
        origin = np.zeros(len(unit))
        if light:
            origin[-2] = 1.0  # neutral light codes as zeros: exactly representable
        return cls(
            unit=np.array(unit),
            names=names,
            distances=distances,
            kinds=kinds,
            light=light,
            body=body,
            camera=camera,
            origin=origin,
        )

    def split(self, values: np.ndarray) -> tuple[np.ndarray, tuple[float, float] | None]:
        """A decoded set as (geometry parameters, light or None); the body motion, if any, is
        `body_of`'s."""
        end = len(values) - 2 * self.light - self._n_body
        light = (float(values[-2]), float(values[-1])) if self.light else None
        return values[:end], light

    def body_of(self, values: np.ndarray) -> np.ndarray | None:
        """The torso's motion in a decoded set, then the camera's if the stream has it
        (`uma.mbc.layers.BODY_NAMES`), or None."""
        if not self.body:
            return None
        end = len(values) - 2 * self.light
        return np.asarray(values[end - self._n_body : end], dtype=np.float64)

    @property
    def _n_body(self) -> int:
        return (len(BODY_KINDS) + len(CAMERA_KINDS) * self.camera) * self.body

    def to_units(self, params: np.ndarray) -> np.ndarray:
        """Parameters (..., 6 + A) in face animation units."""
        origin = 0.0 if self.origin is None else self.origin
        return (np.asarray(params, dtype=np.float64) - origin) / self.unit

    def from_units(self, values: np.ndarray) -> np.ndarray:
        """Face animation units back to the geometry's parameters."""
        origin = 0.0 if self.origin is None else self.origin
        return np.asarray(values, dtype=np.float64) * self.unit + origin


def _distances(model: FaceModel) -> dict[str, float]:
    """The model's FAPU distances (x 1024, as MPEG-4 defines each unit), AU left out."""
    from uma.face.fap_map import fap_units

    try:
        fapu = fap_units(model)
    except FaceError as err:
        raise FaceError(f"{model.name}: the codec's units need its FAPUs: {err}") from None
    return {name: 1024.0 * value for name, value in fapu.by_name.items() if name != "AU"}


def _geometry_units(model: FaceModel, distances: dict[str, float], scale: float) -> list[float]:
    """The unit of each pose parameter and action unit at the description's `scale`."""
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
    return unit
