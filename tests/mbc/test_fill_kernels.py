"""The plate's fill: its compiled steps equal the numpy forms they replace, and both chroma
planes filled over one mask equal each plane filled on its own, to the bit."""

from __future__ import annotations

import numpy as np
import pytest

from uma.mbc import layers
from uma.mbc.fill_kernels import pull_level, settle


def _push_pull(plane: np.ndarray, known: np.ndarray) -> np.ndarray:
    """The plate's push-pull fill as numpy wrote it, one plane at a time."""
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
    return np.where(known, plane, np.clip(np.rint(filled), 0, 255)).astype(plane.dtype)


def _numpy_fill(plane: np.ndarray, known: np.ndarray, edge: str) -> np.ndarray:
    """`layers.fill_unknown` as numpy wrote it before the kernels."""
    return layers._continue_edges(_push_pull(plane, known), known, edge)


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


def _own_band_fill(plane: np.ndarray, known: np.ndarray, edge: str) -> np.ndarray:
    """The numpy fill with its band found for this plane alone (the edge rule as written
    before the band was shared)."""
    import cv2

    filled = _push_pull(plane, known)
    kernel = np.ones((7, 7), np.uint8)
    near = cv2.dilate(known.view(np.uint8), kernel) & ~known.view(np.uint8) & 1
    where = near.view(bool)
    if not where.any():
        return filled
    if edge == "nearest":
        _, labels = cv2.distanceTransformWithLabels(
            (~known).view(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE,
            labelType=cv2.DIST_LABEL_PIXEL,
        )  # fmt: skip
        out = filled.copy()
        out[where] = filled[known][labels[where] - 1]
        return out
    radius = 2 if plane.shape[1] >= 352 else 3  # from CIF's width up, a smaller reach
    painted = cv2.inpaint(np.ascontiguousarray(filled), near, radius, cv2.INPAINT_TELEA)
    return np.where(where, painted, filled)


def _planes(seed: int, height: int = 144, width: int = 176):
    rng = np.random.default_rng(seed)
    ys, xs = np.mgrid[0:height, 0:width]
    u = (100 + 50 * np.sin(xs / 9.0 + seed)).astype(np.uint8) + rng.integers(
        0, 4, (height, width), dtype=np.uint8
    )
    v = (140 + 40 * np.cos(ys / 7.0 - seed)).astype(np.uint8) + rng.integers(
        0, 4, (height, width), dtype=np.uint8
    )
    known = ((xs - width / 2) / (width / 5)) ** 2 + ((ys - height * 0.6) / (height / 3)) ** 2 > 1.0
    known[: height // 8, width * 3 // 4 :] = False
    known &= rng.random((height, width)) > 0.02  # a few holes in the known background
    return np.stack([u, v]), known


@pytest.mark.parametrize("edge", ["nearest", "telea"])
@pytest.mark.parametrize("seed", [0, 1])
def test_two_planes_over_one_mask_are_each_planes_own_fill(edge: str, seed: int) -> None:
    planes, known = _planes(seed)
    got = layers.fill_unknown_planes(planes, known, edge)
    for plane, filled in zip(planes, got, strict=True):
        assert np.array_equal(filled, _own_band_fill(plane, known, edge))
    nothing = np.zeros_like(known)
    assert all(np.all(p == 128) for p in layers.fill_unknown_planes(planes, nothing, edge))


def test_a_plates_chroma_is_each_planes_own_fill() -> None:
    height, width = 96, 128
    rng = np.random.default_rng(3)
    picture = rng.integers(0, 256, (height * 3 // 2, width), dtype=np.uint8)
    person = np.zeros((height, width), bool)
    person[20:90, 40:90] = True
    plate = layers.Plate((width, height))
    plate.update(picture, person)
    known = plate.known[0::2, 0::2] & plate.known[1::2, 1::2]
    seen = plate.seen[height:].reshape(2, height // 2, width // 2)
    chroma = plate.picture[height:].reshape(2, height // 2, width // 2)
    for k in range(2):
        assert np.array_equal(chroma[k], _own_band_fill(seen[k], known, "nearest"))
    assert np.array_equal(
        plate.picture[:height], _own_band_fill(plate.seen[:height], plate.known, "telea")
    )


def _plate_as_before(plate_seen, plate_known, picture, person, fresh):
    """`Plate.update` as written before (fancy indexing, each chroma plane filled on its own):
    (seen, known, picture, started again)."""
    height, width = person.shape
    seen, known = plate_seen.copy(), plate_known.copy()
    outside = ~person if fresh is None else ~person & (fresh | ~known)
    both = outside & known
    again = False
    if both.mean() > 0.05:
        diff = np.abs(
            picture[:height][both].astype(np.int16) - seen[:height][both].astype(np.int16)
        )
        again = float(np.median(diff)) > layers.PLATE_MISMATCH_LEVELS
        if again:
            known[:] = False
    seen[:height][outside] = picture[:height][outside]
    chroma_out = outside[0::2, 0::2] & outside[1::2, 1::2]
    known |= outside
    known_chroma = known[0::2, 0::2] & known[1::2, 1::2]
    out = np.empty_like(seen)
    out[:height] = _own_band_fill(seen[:height], known, "telea")
    planes, new = (p[height:].reshape(2, height // 2, width // 2) for p in (seen, picture))
    filled = out[height:].reshape(2, height // 2, width // 2)
    for k in range(2):
        planes[k][chroma_out] = new[k][chroma_out]
        filled[k] = _own_band_fill(planes[k], known_chroma, "nearest")
    return seen, known, out, again


def test_a_plate_learns_and_fills_as_it_did_before() -> None:
    height, width = 96, 128
    rng = np.random.default_rng(5)
    plate = layers.Plate((width, height))
    person = np.zeros((height, width), bool)
    person[20:90, 40:90] = True
    fresh = np.zeros_like(person)
    fresh[10:60, 30:100] = True
    base = rng.integers(60, 200, (height * 3 // 2, width), dtype=np.uint8)
    steps = [(base, person, None), (base + rng.integers(0, 3, base.shape, dtype=np.uint8),
             np.roll(person, 9, axis=1), fresh), (255 - base, person, None)]  # fmt: skip
    for picture, who, decoded in steps:  # the last departs from the plate: it starts again
        want = _plate_as_before(plate.seen, plate.known, picture, who, decoded)
        reason = plate.update(picture, who, decoded)
        assert (reason != "") == want[3]
        for got, expected in zip((plate.seen, plate.known, plate.picture), want[:3], strict=True):
            assert np.array_equal(got, expected)
    assert reason


def test_telea_reads_a_smaller_radius_from_cif_up_and_only_the_band_moves() -> None:
    """A CIF plate's luma band is Telea's with a 1-px radius (neither 2 nor 3), a QCIF one's
    with 3 as before; outside the band the fill is the same whatever the radius."""
    import cv2

    rng = np.random.default_rng(11)
    ys, xs = np.mgrid[0:288, 0:352]
    plane = (96 + 60 * np.sin(xs / 7.0) + 40 * np.cos(ys / 5.0)).astype(np.uint8)
    plane += rng.integers(0, 6, plane.shape, dtype=np.uint8)
    known = ((xs - 176) / 70.0) ** 2 + ((ys - 170) / 110.0) ** 2 > 1.0
    filled = _push_pull(plane, known)
    kernel = np.ones((7, 7), np.uint8)
    near = cv2.dilate(known.view(np.uint8), kernel) & ~known.view(np.uint8) & 1
    band = near.view(bool)
    got = layers.fill_unknown(plane, known)
    one = np.where(band, cv2.inpaint(filled, near, 1, cv2.INPAINT_TELEA), filled)
    two = np.where(band, cv2.inpaint(filled, near, 2, cv2.INPAINT_TELEA), filled)
    three = np.where(band, cv2.inpaint(filled, near, 3, cv2.INPAINT_TELEA), filled)
    assert np.array_equal(got, one)
    assert not np.array_equal(got, two) and not np.array_equal(got, three)
    assert np.array_equal(got[~band], three[~band])
    small, small_known = np.ascontiguousarray(plane[::2, ::2]), known[::2, ::2].copy()
    small_near = cv2.dilate(small_known.view(np.uint8), kernel) & ~small_known.view(np.uint8) & 1
    small_filled = _push_pull(small, small_known)
    small_three = cv2.inpaint(small_filled, small_near, 3, cv2.INPAINT_TELEA)
    want = np.where(small_near.view(bool), small_three, small_filled)
    assert np.array_equal(layers.fill_unknown(small, small_known), want)
