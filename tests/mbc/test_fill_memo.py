"""The plate's luma fill kept by content equals the fill computed afresh, for every input."""

from __future__ import annotations

import numpy as np

from uma.mbc import layers
from uma.mbc.fill_memo import FillMemo


def _inputs(seed: int, height: int = 48, width: int = 64):
    rng = np.random.default_rng(seed)
    plane = rng.integers(0, 256, (height, width), dtype=np.uint8)
    known = np.ones((height, width), bool)
    known[10:30, 20:44] = False  # a person's hole
    return plane, known


def test_a_kept_fill_is_the_plain_fill_and_a_changed_input_is_filled_again() -> None:
    memo = FillMemo(layers.fill_unknown, entries=2)
    plane, known = _inputs(0)
    first = memo.fill(plane, known)
    again = memo.fill(plane.copy(), known.copy())
    assert memo.hits == 1 and again is first
    assert np.array_equal(first, layers.fill_unknown(plane, known))
    changed = plane.copy()
    changed[5, 5] ^= 1  # one known pixel one level off
    assert np.array_equal(memo.fill(changed, known), layers.fill_unknown(changed, known))
    fewer = known.copy()
    fewer[40, 60] = False
    assert np.array_equal(memo.fill(plane, fewer), layers.fill_unknown(plane, fewer))
    assert np.array_equal(memo.fill(plane, known, "nearest"),
                          layers.fill_unknown(plane, known, "nearest"))  # fmt: skip
    assert memo.hits == 1
    assert not first.flags.writeable
