"""Quantisation and entropy coding of parameter sets: round trips at the quantised values."""

from __future__ import annotations

import numpy as np
import pytest

from uma.face import load_model
from uma.mbc.coding import AdaptiveModels, decode_sets, encode_sets
from uma.mbc.quant import Quantiser, QuantiserConfig
from uma.mbc.units import FaceUnits


@pytest.fixture(scope="module")
def units() -> FaceUnits:
    model = load_model()
    params = np.zeros(6 + model.n_actions)
    params[:3] = (176.0, 144.0, 70.0)
    return FaceUnits.of(model, params)


def test_units_follow_mpeg4_definitions(units: FaceUnits) -> None:
    # Translations in ES/1024 at the description's scale, rotations in 1e-5 rad.
    assert units.unit[0] == pytest.approx(units.distances["ES"] * 70.0 / 1024)
    assert units.unit[3] == 1e-5
    values = np.linspace(-3, 3, units.unit.size)
    assert np.allclose(units.from_units(units.to_units(values)), values)


@pytest.mark.parametrize("global_step", [0.5, 1.0, 2.5])
def test_quantise_dequantise_within_half_a_step(global_step: float) -> None:
    rng = np.random.default_rng(1)
    quantiser = Quantiser(("MNS",) * 7, QuantiserConfig(global_step=global_step))
    code = quantiser.config.global_code
    steps = quantiser.steps(code)
    values = rng.normal(0, 500, (200, 13))
    decoded = quantiser.dequantise_intra(quantiser.intra(values, code), code)
    assert np.all(np.abs(decoded - values) <= steps / 2 + 1e-9)
    reference = decoded[0]
    for row in values[1:]:
        indices = quantiser.predict(row, reference, code)
        reference = quantiser.dequantise_predictive(indices, reference, code)
        assert np.all(np.abs(reference - row) <= steps / 2 + 1e-9)


def _random_sets(rng: np.random.Generator, n: int, p: int) -> list[tuple[bool, np.ndarray]]:
    sets = []
    for k in range(n):
        intra = k % 7 == 0
        if intra:
            sets.append((True, rng.integers(-5000, 5000, p)))
        else:
            # Mostly small residuals, now and then a jump beyond the models' range (escape).
            small = np.rint(rng.laplace(0, 1.5, p)).astype(np.int64)
            jump = rng.random(p) < 0.05
            small[jump] = rng.integers(-3000, 3000, int(jump.sum()))
            sets.append((False, small))
    return sets


def test_intra_and_predictive_sets_round_trip_exactly() -> None:
    rng = np.random.default_rng(2)
    sets = _random_sets(rng, 40, 13)
    words, bits = encode_sets(sets, AdaptiveModels(13))
    assert bits <= 32 * len(words)
    decoded = decode_sets(words, [intra for intra, _ in sets], AdaptiveModels(13))
    for (_, indices), back in zip(sets, decoded, strict=True):
        assert np.array_equal(indices, back)


def test_models_adapt_so_small_residuals_cost_little() -> None:
    rng = np.random.default_rng(3)
    zeros = [(True, rng.integers(-100, 100, 13))] + [(False, np.zeros(13, int))] * 100
    _, bits = encode_sets(zeros, AdaptiveModels(13))
    # 13 x 20 bits for the intra set; the 1,300 zero residuals then cost about a quarter of a
    # bit each (the prior alone would charge them 2.6 bits: log2 of its mass over its peak).
    assert bits - 13 * 20 < 0.3 * 1300


def test_an_index_beyond_the_coder_is_refused() -> None:
    with pytest.raises(ValueError, match="beyond"):
        encode_sets([(True, np.full(13, 1 << 20))], AdaptiveModels(13))
