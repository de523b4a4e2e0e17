"""`uma bench init`'s pieces: exact budgets, ground truth, Yale B registration, subsets."""

import numpy as np
import pytest

from uma.bench.init import _dual_annealing, _summary
from uma.bench.init_cases import is_large_pose, light_angle_deg, rotation_deg
from uma.fit import mde_px, search_box


def test_dual_annealing_spends_exactly_the_budget(template, cases):
    case = cases[0]
    box = search_box(template.fit.params, template.fit.face_width_px)
    result = _dual_annealing(case, template.fit.params, box, 120, np.random.default_rng(0))
    assert result.evaluations == 120
    assert np.all(np.isfinite(result.params)) and box.contains(result.params)


def test_cases_render_their_ground_truth(template, cases):
    from uma.fit import Cost

    for case in cases:
        cost = Cost(template.fit, case.image.astype(np.float32))
        # The rendered pose scores far better than the template's own placement.
        assert float(cost(case.truth)) < 0.25 * float(cost(template.fit.params))
        assert mde_px(template.fit.model, template.fit.params, case.truth) > 1.5
        assert rotation_deg(case) <= np.sqrt(20**2 + 20**2 + 15**2) + 1e-9
        assert is_large_pose(case) == (rotation_deg(case) > 20 or case.shift_frac > 0.08)


def test_light_angles():
    assert light_angle_deg("same") is None
    assert light_angle_deg("A+000E+00") == 0.0
    assert light_angle_deg("A-035E+00") == 35.0
    assert light_angle_deg("A+060E-20") == pytest.approx(62.0, abs=0.1)


def test_summary_counts_failures_with_their_start():
    rows = [
        {"m": {"mde_px": 0.2, "ms": 5.0, "evaluations": 500, "failed": False}},
        {"m": {"mde_px": 9.0, "ms": 7.0, "evaluations": 0, "failed": True}},
    ]
    summary = _summary(rows, "m")
    assert summary["success_rate"] == 0.5 and summary["failures"] == 1
    assert summary["evaluations_median"] == 500  # a failure does not say what it spent
    assert _summary([], "m")["mde_median_px"] is None


def test_yale_lights_are_registered_to_the_template(shared_data):
    import cv2

    from uma.bench.init_yale import read_full, read_registered_lights

    folder = shared_data / "faces" / "yale_b" / "yaleB01"
    reference = read_full(folder / "yaleB01_P00A+000E+00.pgm")
    mild = [folder / f"yaleB01_P00{name}.pgm" for name in ("A+010E+00", "A-005E-10", "A+005E+10")]
    lights = read_registered_lights(reference, mild, (92, 112))
    assert [name for name, _ in lights] == ["A+010E+00", "A-005E-10", "A+005E+10"]
    canvas = read_registered_lights(reference, [folder / "yaleB01_P00A+000E+00.pgm"], (92, 112))
    assert canvas == []  # the template's own light is not a change of light

    def band(image):
        x = np.log1p(image.astype(np.float32))
        return cv2.GaussianBlur(x, (0, 0), 1.0) - cv2.GaussianBlur(x, (0, 0), 3.0)

    from uma.bench.init_yale import canvas as make_canvas

    base = band(make_canvas(reference, (92, 112)))
    window = cv2.createHanningWindow((92, 112), cv2.CV_32F)
    for _, image in lights:
        (dx, dy), _ = cv2.phaseCorrelate(base, band(image), window)
        assert abs(dx) < 0.4 and abs(dy) < 0.4  # unregistered, these lights sit ~0.8 px off


def test_a_faces_folder_without_faces_is_an_error(tmp_path):
    from uma.bench.init_cases import load_templates
    from uma.errors import FaceError
    from uma.face import load_model

    (tmp_path / "s1").mkdir()
    noise = np.random.default_rng(0).integers(0, 255, (112, 92), dtype=np.uint8)
    import cv2

    cv2.imwrite(str(tmp_path / "s1" / "1.png"), noise)
    with pytest.raises(FaceError, match="no face found"):
        load_templates(load_model(), faces=tmp_path, yale=None)
    with pytest.raises(FaceError, match="no Yale B images"):
        load_templates(load_model(), faces=None, yale=tmp_path)
    assert [t.name for t in load_templates(load_model(), faces=None, yale=None)] == ["astronaut"]
