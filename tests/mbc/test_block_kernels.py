"""`uma.mbc.block_kernels` gives the numpy forms it replaced to the bit."""

import numpy as np
import pytest

from uma.mbc.block_kernels import accumulate, block_sse


@pytest.mark.parametrize("seed", range(4))
def test_block_sse_equals_the_float32_sums_of_squares(seed):
    rng = np.random.default_rng(seed)
    rows, cols, block = 5, 7, 8
    picture = rng.integers(0, 256, (rows * block + 6, cols * block + 4), dtype=np.uint8)
    candidate = picture[3 : 3 + rows * block, 1 : 1 + cols * block]  # a strided view
    truth = rng.integers(0, 256, (rows * block, cols * block), dtype=np.uint8)
    truth[:block, :block] = np.where(candidate[:block, :block] > 127, 0, 255)  # the largest errors
    out = np.empty((rows, cols), np.float32)
    block_sse(candidate, truth, block, out)
    error = (candidate.astype(np.float32) - truth.astype(np.float32)) ** 2
    want = error.reshape(rows, block, cols, block).sum(axis=(1, 3))
    assert out.tobytes() == want.tobytes()


@pytest.mark.parametrize("seed", range(4))
def test_accumulate_equals_the_numpy_blend_on_strided_views(seed):
    rng = np.random.default_rng(seed)
    base = rng.uniform(0, 255, (2, 20, 24)).astype(np.float32)
    mixed = base + rng.normal(0, 3, base.shape).astype(np.float32)
    candidate = rng.integers(0, 256, (2, 20, 24), dtype=np.uint8)
    weight = rng.uniform(0, 1, (1, 40, 24)).astype(np.float32)[:, ::2]  # strided, as a half plane
    weight[0, :5] = 0.0
    want = mixed.copy()
    want += weight * (candidate.astype(np.float32) - base)
    for plane in range(2):
        accumulate(mixed[plane], base[plane], candidate[plane], weight[0])
    assert mixed.tobytes() == want.tobytes()
