"""The plate's compiled fill steps equal the numpy forms they replace, to the bit."""

from __future__ import annotations

import numpy as np
import pytest

from uma.mbc import layers
from uma.mbc.fill_kernels import pull_level, settle


def _numpy_fill(plane: np.ndarray, known: np.ndarray, edge: str) -> np.ndarray:
    """`layers.fill_unknown` as numpy wrote it before the kernels."""
    import cv2

    weight = known.astype(np.float32)
    values = plane.astype(np.float32) * weight
    levels = [(values, weight)]
    while min(levels[-1][0].shape) > 2:
        v, w = levels[-1]
        size = (max(v.shape[1] // 2, 1), max(v.shape[0] // 2, 1))
        levels.append((cv2.resize(v, size, interpolation=cv2.INTER_AREA),
                       cv2.resize(w, size, interpolation=cv2.INTER_AREA)))  # fmt: skip
    v, w = levels[-1]
    filled = np.where(w > 1e-6, v / np.maximum(w, 1e-6), float(values.sum() / weight.sum()))
    for v, w in reversed(levels[:-1]):
        up = cv2.resize(filled, (v.shape[1], v.shape[0]), interpolation=cv2.INTER_LINEAR)
        trust = np.clip(w, 0.0, 1.0)
        filled = trust * (v / np.maximum(w, 1e-6)) + (1.0 - trust) * up
    out = np.where(known, plane, np.clip(np.rint(filled), 0, 255)).astype(plane.dtype)
    return layers._continue_edges(out, known, edge)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_kernels_equal_the_numpy_forms(seed: int) -> None:
    rng = np.random.default_rng(seed)
    height, width = rng.integers(2, 200, 2)
    weight = rng.random((height, width)).astype(np.float32) * 1.5
    weight[rng.random((height, width)) < 0.3] = 0.0
    values = (rng.random((height, width)) * 300).astype(np.float32) * weight
    up = (rng.random((height, width)) * 255).astype(np.float32)
    trust = np.clip(weight, 0.0, 1.0)
    want = trust * (values / np.maximum(weight, 1e-6)) + (1.0 - trust) * up
    got = np.empty_like(values)
    pull_level(values, weight, up, np.float32(1e-6), got)
    assert want.dtype == np.float32 and np.array_equal(got, want)
    plane = rng.integers(0, 256, (height, width), dtype=np.uint8)
    known = rng.random((height, width)) < 0.5
    filled = (rng.random((height, width)) * 300 - 20).astype(np.float32)
    filled[0, 0], filled[-1, -1] = 2.5, 3.5  # halves round to even
    want = np.where(known, plane, np.clip(np.rint(filled), 0, 255)).astype(np.uint8)
    got = np.empty_like(plane)
    settle(plane, known, filled, got)
    assert np.array_equal(got, want)


@pytest.mark.parametrize("edge", ["telea", "nearest"])
def test_the_plate_fill_is_the_numpy_one(edge: str) -> None:
    """A CIF plate with a person-shaped hole and a strided chroma-like view."""
    rng = np.random.default_rng(7)
    ys, xs = np.mgrid[0:288, 0:352]
    plane = (96 + 60 * np.sin(xs / 17.0) + 40 * np.cos(ys / 11.0)).astype(np.uint8)
    plane += rng.integers(0, 6, plane.shape, dtype=np.uint8)
    known = ((xs - 176) / 70.0) ** 2 + ((ys - 170) / 110.0) ** 2 > 1.0
    known[:20, 300:] = False
    for p, k in ((plane, known), (plane[::2, ::2], known[::2, ::2])):
        assert np.array_equal(layers.fill_unknown(p, k, edge), _numpy_fill(p, k, edge))
