"""Exact cuts give what the plain calls give: the push-pull without its finest
level's pull, weights zeroed by OpenCV's masked copy, and the block map's ranked gains."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from uma.fit.cost import batch_visible
from uma.mbc.encoder import FaceTracker
from uma.mbc.fill_kernels import pull_level, settle
from uma.mbc.layered_kernels import zero_where
from uma.mbc.layers import _push_pull


def test_weights_zeroed_by_the_masked_copy_are_the_boolean_index_s():
    rng = np.random.default_rng(4)
    weight = rng.random((40, 52)).astype(np.float32) - np.float32(0.1)
    where = np.zeros((60, 80), bool)
    where[10:50, 20:72] = rng.random((40, 52)) < 0.5
    expected = weight.copy()
    expected[where[10:50, 20:72]] = 0.0
    zero_where(weight, where[10:50, 20:72])  # a view, as the drawing's masks are
    np.testing.assert_array_equal(weight, expected)
    assert not np.signbit(weight[where[10:50, 20:72]]).any()


def test_the_ranked_gains_are_the_loop_s():
    """The blocks that gain, most first, ties in index order, as the list loop ranked them."""
    rng = np.random.default_rng(6)
    gain = rng.integers(-3, 4, 256).astype(np.float32)
    gain[:5] = np.inf
    gain[5] = np.nan
    expected = [k for k in np.argsort(-gain, kind="stable") if gain[k] > 0]
    ranked = np.argsort(-gain, kind="stable")
    assert ranked[gain[ranked] > 0].tolist() == [int(k) for k in expected]


def _push_pull_every_level(plane, known, weights):
    """The push-pull as it was: every level pulled, the finest too, then settled."""
    values = plane.astype(np.float32) * weights[0]
    levels = [values]
    for w in weights[1:]:
        levels.append(
            cv2.resize(levels[-1], (w.shape[1], w.shape[0]), interpolation=cv2.INTER_AREA)
        )
    v, w = levels[-1], weights[-1]
    filled = np.where(w > 1e-6, v / np.maximum(w, 1e-6), float(values.sum() / weights[0].sum()))
    for v, w in zip(reversed(levels[:-1]), reversed(weights[:-1]), strict=True):
        up = cv2.resize(filled, (v.shape[1], v.shape[0]), interpolation=cv2.INTER_LINEAR)
        filled = np.empty_like(v)
        pull_level(v, w, up, np.float32(1e-6), filled)
    out = np.empty_like(plane)
    settle(np.ascontiguousarray(plane), known, filled, out)
    return out


@pytest.mark.parametrize("shape", [(288, 352), (144, 176), (37, 53), (3, 5), (2, 9)])
@pytest.mark.parametrize("share", [0.02, 0.4, 0.97])
def test_the_push_pull_without_the_finest_pull_is_the_same(shape, share):
    """The finest level's weights are 0 or 1: its pull is the plane where known (which the
    settling keeps anyway) and the coarser level upsampled elsewhere, to the bit."""
    rng = np.random.default_rng(int(share * 100) + shape[0])
    plane = rng.integers(0, 256, shape, dtype=np.uint8)
    known = rng.random(shape) < share
    known[0, 0] = True
    weights = [known.astype(np.float32)]
    while min(weights[-1].shape) > 2:
        w = weights[-1]
        size = (max(w.shape[1] // 2, 1), max(w.shape[0] // 2, 1))
        weights.append(cv2.resize(w, size, interpolation=cv2.INTER_AREA))
    expected = _push_pull_every_level(plane, known, weights)
    np.testing.assert_array_equal(_push_pull(plane, known, weights), expected)


def test_the_gate_s_shortcut_keeps_every_pixel_the_einsum_keeps(head, head_frames):
    """With every vertex a pixel inside the picture, the pixels' positions (the einsum the gate
    skips) all land inside it; moved to the picture's edge, the einsum still decides."""
    from uma.fit.kernels import project_batch

    tracker = FaceTracker(head.description, rng=0)
    gate, checked = tracker.gate, 0
    for index, picture in enumerate(head_frames):
        result = tracker.track(picture, frame=index)
        if not result:
            continue
        image = np.asarray(picture, np.float32)
        for shift in (0.0, -result.params[0] + 20.0):  # as tracked; at the left edge
            params = result.params.copy()
            params[0] += shift
            samples, kept = gate._sample(image, params)
            points = project_batch(gate._vertices, gate._units, np.ascontiguousarray(params[None]))
            where = np.einsum("kc,kcd->kd", gate._bary, points[0][gate._corners])
            height, width = image.shape
            inside = (where[:, 0] >= 0) & (where[:, 0] <= width - 1)
            inside &= (where[:, 1] >= 0) & (where[:, 1] <= height - 1)
            visible = batch_visible(gate.template.model, points)[0][gate._tri]
            expected = visible & inside & np.isfinite(samples)
            np.testing.assert_array_equal(kept, expected)
            checked += 1
    assert checked >= 20
