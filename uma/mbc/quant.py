"""Quantisation of face parameters, as MPEG-4 FBA does it: a step per parameter times a global step.

Units: values in face animation units (`uma.mbc.units`); steps in the same units; quantised
values are integers (int64).

Each parameter has its own step (`QuantiserConfig.steps`, the counterpart of MPEG-4's per-FAP
quantisation step), multiplied by one global step, the rate control: doubling it roughly
halves the precision and saves about one bit per parameter and frame. An intra set quantises
the values themselves; a predictive set quantises the residual to the previous *decoded*
values, so the encoder's reference is exactly the decoder's and the two never drift. Either
way the error of every decoded value stays within half its step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["QuantiserConfig", "Quantiser", "GLOBAL_STEP_SCALE"]

# The global step travels in each packet as one byte: code / GLOBAL_STEP_SCALE (1/16 to ~16).
GLOBAL_STEP_SCALE = 16.0
# Pose: tx, ty (ES/1024), scale (1/1024), rx, ry, rz (1e-5 rad). At global step 1 a translation
# step is ~0.17 px on a CIF face, a roll step 0.09 degree; pitch and yaw, which move points
# about a third as far for an angle (by depth, not radius), 0.29 degree. Chosen with the global
# step (1.5) on data the README does not quote (talking head seed 1, akiyo's and carphone's
# frames 150-299): payload 1.27, 1.59, 1.79 kbit/s at 0.18, 0.01, 0.01 dB face-region loss;
# global step 2 saves 0.04-0.16 kbit/s for 0.36 dB on the talking head.
DEFAULT_POSE_STEPS = (4.0, 4.0, 3.0, 500.0, 500.0, 150.0)
# Action units, by the face distance they are measured in (1/1024 of it, `uma.mbc.units`):
# at global step 1 a step moves the mouth's most moved vertex by 0.9 % of ES (0.4 px on a CIF
# face), the brows' and eyelids' by 0.4 % (0.17 px): the precision chosen (on the held-out
# halves) before the units were mbcdata's FAPUs, kept in the new units.
DEFAULT_ACTION_STEPS = (("MNS", 32.0), ("MW", 12.0), ("ENS", 5.0), ("IRISD", 24.0))
# Light (`uma.mbc.units.LIGHT_UNITS`): at the default global step 1.5 a gain step of 1.2 %
# (0.6 level on a face of mid-grey 100 levels above black, rounding at half a step) and an
# offset step of 0.75 level; an action-step entry of the same kind overrides them.
LIGHT_STEPS = (("LIGHT_GAIN", 8.0), ("LIGHT_OFFSET", 12.0))
# The torso's motion (`uma.mbc.units.BODY_KINDS`): at the global step 1.5 a shift step of 6
# ES/1024 (about 0.35 px on a CIF face), rotation 0.0045 rad.
BODY_STEPS = (("BODY_SHIFT", 4.0), ("BODY_ROTATION", 300.0), ("CAMERA_SHIFT", 4.0))


@dataclass(frozen=True)
class QuantiserConfig:
    """Per-parameter steps (pose, then one for every action unit) and the global step."""

    pose_steps: tuple[float, ...] = DEFAULT_POSE_STEPS
    action_steps: tuple[tuple[str, float], ...] = DEFAULT_ACTION_STEPS
    global_step: float = 1.5

    def __post_init__(self) -> None:
        if len(self.pose_steps) != 6 or not all(s > 0 for s in self.pose_steps):
            raise ValueError(f"quantiser: six positive pose steps expected, got {self.pose_steps}")
        if not self.action_steps or not all(step > 0 for _, step in self.action_steps):
            raise ValueError(f"quantiser: positive action steps expected, got {self.action_steps}")
        code = round(self.global_step * GLOBAL_STEP_SCALE)
        if not 1 <= code <= 255 or abs(code / GLOBAL_STEP_SCALE - self.global_step) > 1e-9:
            raise ValueError(
                f"quantiser: global_step must be a multiple of 1/16 in [1/16, 255/16], got "
                f"{self.global_step}"
            )

    @property
    def global_code(self) -> int:
        """The global step as the byte a packet carries."""
        return round(self.global_step * GLOBAL_STEP_SCALE)


class Quantiser:
    """Steps for the pose and one action unit per entry of `kinds` (the face distance each is
    measured in, `FaceUnits.kinds`; an unknown kind takes MNS's step); stateless (the
    reference is passed in)."""

    def __init__(self, kinds: tuple[str, ...], config: QuantiserConfig = QuantiserConfig()):
        steps = dict(LIGHT_STEPS) | dict(BODY_STEPS) | dict(config.action_steps)
        self.config = config
        self.base = np.array(
            list(config.pose_steps) + [steps.get(k, steps.get("MNS", 1.0)) for k in kinds],
            dtype=np.float64,
        )
        self.n_params = self.base.size

    def steps(self, global_code: int) -> np.ndarray:
        """Every parameter's step at a global step code (the packet's byte)."""
        return self.base * (global_code / GLOBAL_STEP_SCALE)

    def intra(self, values: np.ndarray, global_code: int) -> np.ndarray:
        """Quantised indices of `values` (absolute)."""
        return np.rint(np.asarray(values, dtype=np.float64) / self.steps(global_code)).astype(
            np.int64
        )

    def predict(self, values: np.ndarray, reference: np.ndarray, global_code: int) -> np.ndarray:
        """Quantised residual indices of `values` against the decoded `reference`."""
        residual = np.asarray(values, dtype=np.float64) - reference
        return np.rint(residual / self.steps(global_code)).astype(np.int64)

    def dequantise_intra(self, indices: np.ndarray, global_code: int) -> np.ndarray:
        return np.asarray(indices, dtype=np.float64) * self.steps(global_code)

    def dequantise_predictive(
        self, indices: np.ndarray, reference: np.ndarray, global_code: int
    ) -> np.ndarray:
        return reference + np.asarray(indices, dtype=np.float64) * self.steps(global_code)
