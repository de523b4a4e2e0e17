"""Fitting works with another wireframe: Candide-3 (113 vertices, 65 action units)."""

import numpy as np
import pytest

from uma.bench.init_cases import Template, make_cases
from uma.face import make_params, read_wfm
from uma.fit import fit_face, mde_px, search_box
from uma.fit.cost import FitTemplate


@pytest.mark.parametrize("method", ["saabs", "hybrid", "gauss_newton"])
def test_candide3_known_poses(shared_data, template, method):
    model = read_wfm(shared_data / "faces" / "candide3" / "candide3.wfm")
    params = make_params(model, tx_px=46, ty_px=60, scale_px=40)
    fit = FitTemplate.build(model, template.fit.image, params)
    cases = make_cases([Template("candide", fit, None)], 2, rng=1)
    box = search_box(params, fit.face_width_px)
    for seed, case in enumerate(cases):
        result = fit_face(
            fit, case.image.astype(np.float32), method=method, start=params, box=box, rng=seed
        )
        assert result
        assert mde_px(model, result.params, case.truth) < 0.8 < mde_px(model, params, case.truth)
