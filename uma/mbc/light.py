"""What the encoder measures against its mirror of the receiver: the face's light per frame,
and the head ring that renders its frames best.

Units: gain unitless, offset in luma levels (BT.601 limited range); head ring in face-outline
radii.

The encoder renders what the receiver will show (`uma.mbc.scene_render.SceneRenderer`, the
same reference) and fits the frame's face luma as gain * rendered + offset by least squares
over the face's pixels. The result is clipped into the renderer's ranges, so a frame the fit
cannot explain (a flat face, a hand over it) never sends absurd light.
"""

from __future__ import annotations

import numpy as np

from uma.face.describe import ContentDescription
from uma.mbc.errors import SceneError
from uma.mbc.scene_render import (
    HEAD_RING_CHOICES,
    LIGHT_GAIN_RANGE,
    LIGHT_OFFSET_RANGE,
    SceneRenderer,
)

__all__ = ["estimate_light", "measure_light", "choose_head_ring", "NEUTRAL_LIGHT"]

NEUTRAL_LIGHT = (1.0, 0.0)
_MIN_PIXELS = 64
_MIN_STD = 2.0  # levels: a flatter rendering says nothing about gain


def estimate_light(
    rendered: np.ndarray, actual: np.ndarray, mask: np.ndarray, *, every: int = 3
) -> tuple[float, float]:
    """(gain, offset) that best map `rendered`'s luma onto `actual`'s over `mask` (H, W),
    reading every `every`-th masked pixel (all three of one shape); neutral where too few
    pixels or no contrast."""
    if not rendered.shape == actual.shape == mask.shape:
        raise ValueError(f"light: expected pictures of the mask's shape {mask.shape}, got "
                         f"{rendered.shape} and {actual.shape}")  # fmt: skip
    # The masked pixels indexed once, in the mask's row order, through flat views of the box.
    flat = np.flatnonzero(mask)[::every]
    if flat.size < _MIN_PIXELS:
        return NEUTRAL_LIGHT
    r = np.ascontiguousarray(rendered).reshape(-1)[flat].astype(np.float64)
    a = np.ascontiguousarray(actual).reshape(-1)[flat].astype(np.float64)
    spread = r.std()
    if not np.isfinite(spread) or spread < _MIN_STD:
        return NEUTRAL_LIGHT
    r_mean, a_mean = r.mean(), a.mean()
    gain = float(np.mean((r - r_mean) * (a - a_mean)) / spread**2)
    gain = float(np.clip(gain, *LIGHT_GAIN_RANGE))
    offset = float(np.clip(a_mean - gain * r_mean, *LIGHT_OFFSET_RANGE))
    return gain, offset


def measure_light(renderer, luma: np.ndarray, params: np.ndarray) -> tuple[float, float]:
    """The light of the face at `params` on `luma` (H, W) against what `renderer` (a
    `SceneRenderer`, the receiver's reference) draws there."""
    patch, mask, (x0, y0) = renderer.face_luma(params)
    h, w = patch.shape
    return estimate_light(patch, luma[y0 : y0 + h, x0 : x0 + w], mask)


def choose_head_ring(
    description: ContentDescription,
    reference: np.ndarray,
    reference_params: np.ndarray,
    pictures: list[np.ndarray],
    params: list[np.ndarray],
    choices: tuple[float, ...] = HEAD_RING_CHOICES,
) -> float:
    """The head ring (in face-outline radii, one of `choices`) whose rendering from `reference`
    (YUV 4:2:0, the model at `reference_params`) at each of `params`, relit as the encoder
    measures light, comes nearest the matching `pictures` (YUV 4:2:0) in whole-frame luma: the
    sender's choice, from frames it has coded, for the rest of the call."""
    height, width = reference.shape[0] * 2 // 3, reference.shape[1]
    if not params or len(params) != len(pictures):
        raise SceneError(f"head ring: expected pictures with a pose each, got {len(pictures)} "
                         f"pictures and {len(params)} poses")  # fmt: skip
    errors = []
    for ring in choices:
        renderer = SceneRenderer(description, (width, height), head_ring_outlines=ring)
        renderer.set_reference(reference, reference_params)
        total = 0.0
        for picture, pose in zip(pictures, params, strict=True):
            luma = picture[:height]
            shown, _ = renderer.render(pose, measure_light(renderer, luma, pose))
            total += float(np.mean((shown[:height].astype(np.float32) - luma) ** 2))
        errors.append(total)
    return float(choices[int(np.argmin(errors))])
