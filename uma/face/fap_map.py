"""FAPs <-> uma model parameters: FAP units of a face and the mapping onto its action units.

Units: FAP values are integers in face animation parameter units (FAPUs): ES, ENS, MNS, MW and
IRISD are a neutral-face distance / 1024 (ISO/IEC 14496-2, Annex C), AU is 1e-5 rad. Model
parameters are radians (rx_rad, ry_rad, rz_rad) and unitless action-unit coefficients.

Mapping to uma's model (`FAP_TABLE`, and the README): each low-level FAP moves one feature
point along one axis by value x FAPU. The model's action units move those points too, so a set
of FAPs is turned into action units by least squares on the displacements they describe
(model units: every FAP weighs by the distance it stands for), and back by projecting the
units' displacements onto each FAP's point and axis. FAPs of one side and of inner and outer
lip contours all constrain uma's symmetric units; FAPs the model has no unit for (tongue,
cheeks, ears, eyeballs, nose, FAPs 14-18, 23-30, 37-47, 61-68) are read and written but not
mapped. Head rotation is FAPs 48-50 in AU: pitch (positive: nose down) = rx_rad, yaw (positive:
the head turns to the subject's left) = ry_rad, roll (positive: the top of the head tilts to
the subject's right) = rz_rad, as the model's R = Rz Ry Rx turns those ways for positive angles.
FAPs displace a face from its neutral state: `faps_to_parameters` adds them to a base
parameter vector (the template's pose and expression), `parameters_to_faps` measures from it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from uma.errors import FaceError
from uma.face.fap import FapSequence
from uma.face.geometry import N_POSE
from uma.face.model import FaceModel

__all__ = [
    "FAP_TABLE",
    "ROTATION_FAPS",
    "AU_RAD",
    "FapUnits",
    "fap_units",
    "fap_matrix",
    "faps_to_parameters",
    "parameters_to_faps",
    "fap_sequence",
]

AU_RAD = 1e-5  # the angle unit of FAPs 23-26, 47-50

# FAP -> (model feature point, axis, sign, FAPU): a positive value moves the point by
# value x FAPU along sign x axis in model coordinates (x to the subject's left, y up).
# Lip points are named as uma's wireframe names them (2.6/8.5 left of the middle of the upper
# inner/outer lip, 2.8/8.7 the lower; odd-numbered corners 2.4/8.3 on the subject's left).
FAP_TABLE: dict[int, tuple[str, str, int, str]] = {
    3: ("2.1", "y", -1, "MNS"),  # open_jaw: chin down
    4: ("2.2", "y", -1, "MNS"),  # lower_t_midlip
    5: ("2.3", "y", +1, "MNS"),  # raise_b_midlip
    6: ("2.4", "x", +1, "MW"),  # stretch_l_cornerlip: left corner outward
    7: ("2.5", "x", -1, "MW"),  # stretch_r_cornerlip
    8: ("2.6", "y", -1, "MNS"),  # lower_t_lip_lm
    9: ("2.7", "y", -1, "MNS"),  # lower_t_lip_rm
    10: ("2.8", "y", +1, "MNS"),  # raise_b_lip_lm
    11: ("2.9", "y", +1, "MNS"),  # raise_b_lip_rm
    12: ("2.4", "y", +1, "MNS"),  # raise_l_cornerlip
    13: ("2.5", "y", +1, "MNS"),  # raise_r_cornerlip
    19: ("3.1", "y", -1, "IRISD"),  # close_t_l_eyelid: upper lid down
    20: ("3.2", "y", -1, "IRISD"),  # close_t_r_eyelid
    21: ("3.3", "y", +1, "IRISD"),  # close_b_l_eyelid: lower lid up
    22: ("3.4", "y", +1, "IRISD"),  # close_b_r_eyelid
    31: ("4.1", "y", +1, "ENS"),  # raise_l_i_eyebrow
    32: ("4.2", "y", +1, "ENS"),  # raise_r_i_eyebrow
    33: ("4.3", "y", +1, "ENS"),  # raise_l_m_eyebrow
    34: ("4.4", "y", +1, "ENS"),  # raise_r_m_eyebrow
    35: ("4.5", "y", +1, "ENS"),  # raise_l_o_eyebrow
    36: ("4.6", "y", +1, "ENS"),  # raise_r_o_eyebrow
    51: ("8.1", "y", -1, "MNS"),  # lower_t_midlip_o
    52: ("8.2", "y", +1, "MNS"),  # raise_b_midlip_o
    53: ("8.3", "x", +1, "MW"),  # stretch_l_cornerlip_o
    54: ("8.4", "x", -1, "MW"),  # stretch_r_cornerlip_o
    55: ("8.5", "y", -1, "MNS"),  # lower_t_lip_lm_o
    56: ("8.6", "y", -1, "MNS"),  # lower_t_lip_rm_o
    57: ("8.7", "y", +1, "MNS"),  # raise_b_lip_lm_o
    58: ("8.8", "y", +1, "MNS"),  # raise_b_lip_rm_o
    59: ("8.3", "y", +1, "MNS"),  # raise_l_cornerlip_o
    60: ("8.4", "y", +1, "MNS"),  # raise_r_cornerlip_o
}
# Head rotation FAP -> index in the parameter vector (rx_rad, ry_rad, rz_rad), in AU.
ROTATION_FAPS: dict[int, int] = {48: 3, 49: 4, 50: 5}


@dataclass(frozen=True)
class FapUnits:
    """FAPUs of a face in model units (a neutral distance / 1024), and AU in radians."""

    es: float  # eye separation: pupil to pupil (3.5-3.6)
    ens: float  # eye-nose separation: the pupils' line to the nose's base
    mns: float  # mouth-nose separation: the nose's base to the mouth's line (2.2)
    mw: float  # mouth width: corner to corner (8.3-8.4)
    irisd: float  # iris diameter: upper to lower eyelid (3.1-3.3)
    au: float = AU_RAD
    by_name: dict[str, float] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        units = {"ES": self.es, "ENS": self.ens, "MNS": self.mns, "MW": self.mw}
        units |= {"IRISD": self.irisd, "AU": self.au}
        for name, value in units.items():
            if not (np.isfinite(value) and value > 0):
                raise FaceError(f"FAPU {name}: expected a positive distance, got {value}")
        object.__setattr__(self, "by_name", units)


def fap_units(model: FaceModel) -> FapUnits:
    """The FAPUs of `model`'s neutral face (its vertices with no action unit applied: pass the
    personal model to get the person's units).

    MPEG-4 measures ENS and MNS to point 9.15, the bottom of the nose; uma's wireframe puts
    its 9.15 on the bridge, so the nose's base here is the nostrils' midpoint (9.1, 9.2).
    """
    need = ["3.5", "3.6", "3.1", "3.3", "9.1", "9.2", "2.2", "8.3", "8.4"]
    index = dict(zip(need, model.feature_indices(need), strict=True))
    v = model.vertices

    def at(name: str) -> np.ndarray:
        return v[index[name]]

    pupils = (at("3.5") + at("3.6")) / 2
    nose = (at("9.1") + at("9.2")) / 2
    try:
        return FapUnits(
            es=float(np.linalg.norm(at("3.5") - at("3.6"))) / 1024,
            ens=float(pupils[1] - nose[1]) / 1024,
            mns=float(nose[1] - at("2.2")[1]) / 1024,
            mw=float(np.linalg.norm(at("8.3") - at("8.4"))) / 1024,
            irisd=float(at("3.1")[1] - at("3.3")[1]) / 1024,
        )
    except FaceError as err:
        raise FaceError(f"{model.name}: {err}") from None


def fap_matrix(model: FaceModel, units: FapUnits) -> tuple[tuple[int, ...], np.ndarray]:
    """The FAPs `model` can express and the (F, A) matrix of FAP value per unit action: row f
    is how far each action unit moves FAP f's point along its axis, in FAP f's unit."""
    axis = {"x": 0, "y": 1}
    numbers = tuple(k for k, (point, *_) in FAP_TABLE.items() if point in model.feature_points)
    matrix = np.zeros((len(numbers), model.n_actions))
    for row, k in enumerate(numbers):
        point, along, sign, unit = FAP_TABLE[k]
        vertex = model.feature_points[point]
        matrix[row] = sign * model.action_units[:, vertex, axis[along]] / units.by_name[unit]
    return numbers, matrix


def faps_to_parameters(
    faps: Mapping[int, int | float],
    model: FaceModel,
    units: FapUnits,
    *,
    base: np.ndarray | None = None,
) -> np.ndarray:
    """Model parameters (6 + A,) for one frame of FAPs: `base` (default a unit-scale face at the
    origin, neutral) with the head rotation of FAPs 48-50 added, and the action units that best
    reproduce the mapped low-level FAPs given (least squares on the displacements, in model
    units). FAPs the frame does not give do not constrain the fit; an action unit no given FAP
    moves stays at its base value."""
    params = (
        np.concatenate([[0.0, 0.0, 1.0, 0.0, 0.0, 0.0], np.zeros(model.n_actions)])
        if base is None
        else np.array(base, dtype=np.float64)
    )
    if params.shape != (N_POSE + model.n_actions,):
        raise FaceError(f"base: expected {N_POSE + model.n_actions} parameters, got {params.shape}")
    for k, slot in ROTATION_FAPS.items():
        if k in faps:
            params[slot] += float(faps[k]) * units.au
    numbers, matrix = fap_matrix(model, units)
    given = [row for row, k in enumerate(numbers) if k in faps]
    if given and model.n_actions:
        scale = np.array([units.by_name[FAP_TABLE[numbers[row]][3]] for row in given])
        a = matrix[given] * scale[:, None]  # model units per unit action
        b = np.array([float(faps[numbers[row]]) for row in given]) * scale
        params[N_POSE:] += np.linalg.lstsq(a, b, rcond=None)[0]
    return params


def parameters_to_faps(
    params: np.ndarray,
    model: FaceModel,
    units: FapUnits,
    *,
    base: np.ndarray | None = None,
) -> dict[int, int]:
    """The FAPs (rounded to whole FAPUs) of `params` (6 + A,) measured from `base` (default
    neutral and frontal): head rotation (48-50) and every low-level FAP the model expresses."""
    params = np.asarray(params, dtype=np.float64)
    if params.shape != (N_POSE + model.n_actions,):
        raise FaceError(f"expected {N_POSE + model.n_actions} parameters, got {params.shape}")
    delta = params - (0.0 if base is None else np.asarray(base, dtype=np.float64))
    faps = {k: int(np.rint(delta[slot] / units.au)) for k, slot in ROTATION_FAPS.items()}
    numbers, matrix = fap_matrix(model, units)
    values = matrix @ delta[N_POSE:]
    faps |= {k: int(np.rint(v)) for k, v in zip(numbers, values, strict=True)}
    return dict(sorted(faps.items()))


def fap_sequence(
    track: np.ndarray,
    model: FaceModel,
    units: FapUnits,
    *,
    fps: float,
    name: str,
    base: np.ndarray | None = None,
) -> FapSequence:
    """The `FapSequence` of a parameter track (F, 6 + A), e.g. a tracker's output, each frame
    measured from `base` by `parameters_to_faps`; `write_fap` saves it."""
    track = np.asarray(track, dtype=np.float64)
    if track.ndim != 2:
        raise FaceError(
            f"{name}: expected a track of shape (frames, parameters), got {track.shape}"
        )
    frames = tuple(parameters_to_faps(row, model, units, base=base) for row in track)
    return FapSequence(name=name, fps=fps, frames=frames)
