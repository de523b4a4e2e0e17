"""The hybrid: two views of the images for SAABs' global search, the better polished."""

import numpy as np
import pytest

from uma.bench.init_cases import make_cases
from uma.fit import HybridConfig, fit_face, mde_px, search_box
from uma.fit.gauss_newton import GaussNewtonConfig
from uma.fit.hybrid import LIGHT_ROBUST, SAME_LIGHT, PolishStep


def _side_lit(image: np.ndarray, strength: float) -> np.ndarray:
    """A light from the right: the gain falls smoothly from 1 + s to 1 - s across the picture."""
    xs = np.linspace(-1.0, 1.0, image.shape[1], dtype=np.float32)
    return image * np.clip(1.0 + strength * np.tanh(3.0 * xs), 0.05, None)[None, :]


@pytest.fixture(scope="module")
def side_lit(template):
    cases = make_cases([template], 6, rng=5)
    return [(_side_lit(c.image.astype(np.float32), 0.7), c.truth) for c in cases]


def _hybrid(template, image, seed, config=None):
    """The hybrid from the template's placement, in the search box around it."""
    fit = template.fit
    config = config or HybridConfig()
    box = search_box(fit.params, fit.face_width_px)
    return fit_face(
        fit, image, method="hybrid", start=fit.params, box=box, rng=seed, hybrid_config=config
    )


def _errors(template, side_lit, config):
    out = []
    for seed, (image, truth) in enumerate(side_lit):
        result = _hybrid(template, image, seed, config)
        out.append(mde_px(template.fit.model, result.params, truth) if result else np.inf)
    return np.array(out)


def test_the_band_passed_view_finds_the_face_under_side_light(template, side_lit):
    both = _errors(template, side_lit, HybridConfig())
    assert np.median(both) < 1.0 and np.mean(both < 1.5) >= 5 / 6
    # The same-light view alone is pulled off by the shading: the second view is what finds it.
    same = _errors(template, side_lit, HybridConfig(chains=(SAME_LIGHT,), retry_chains=()))
    assert np.mean(same < 1.5) <= 2 / 6
    # A poor match after the first searches sends the hybrid into the band-passed view again.
    retried = _errors(
        template, side_lit, HybridConfig(chains=(SAME_LIGHT,), retry_chains=(LIGHT_ROBUST,))
    )
    assert np.mean(retried < 1.5) >= 5 / 6


def test_a_good_match_is_not_searched_again(template, cases):
    image = cases[0].image.astype(np.float32)
    plain = _hybrid(template, image, 0, HybridConfig(retry_chains=()))
    retrying = _hybrid(template, image, 0)  # the template's own light: a close match
    assert plain and 1.0 - plain.cost > HybridConfig().retry_below
    assert retrying.evaluations == plain.evaluations
    always = _hybrid(template, image, 0, HybridConfig(retry_below=1.0))
    assert always.evaluations > plain.evaluations + 300


def test_the_result_counts_every_chain(template, cases):
    image = cases[0].image.astype(np.float32)
    one = _hybrid(template, image, 0, HybridConfig(chains=(LIGHT_ROBUST,)))
    two = _hybrid(template, image, 0)
    assert one and two
    assert two.evaluations > one.evaluations + 300  # a second global search of 304
    with pytest.raises(ValueError):
        HybridConfig(chains=())
    with pytest.raises(ValueError):
        HybridConfig(retry_below=1.5)
    with pytest.raises(ValueError):
        PolishStep(GaussNewtonConfig(), blur=0.05, band=0.02)  # a band narrower than the blur
