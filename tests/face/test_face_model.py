import numpy as np
import pytest

from uma.errors import FaceError
from uma.face import load_model, make_params, project, read_wfm, visible_triangles
from uma.face.build import build_wireframe


def test_stored_wireframe_matches_its_generator():
    built, stored = build_wireframe(), load_model()
    assert np.allclose(built.vertices, stored.vertices, atol=1e-5)
    assert np.array_equal(built.triangles, stored.triangles)
    assert np.allclose(built.action_units, stored.action_units, atol=1e-5)
    assert built.feature_points == stored.feature_points


def test_wireframe_has_what_the_codec_needs():
    model = load_model()
    assert 100 <= len(model.triangles) <= 200
    for unit in ("jaw_drop", "lip_stretch", "lip_corner_depressor", "brow_raise", "eye_close"):
        assert unit in model.action_unit_names
    assert {"3.5", "3.6", "9.3", "8.3", "8.4", "2.1"} <= set(model.feature_points)
    # Every triangle faces the camera in the frontal pose (consistent winding).
    params = make_params(model, tx_px=100, ty_px=100, scale_px=50)
    assert visible_triangles(model, params).all()


def test_turning_away_culls_triangles():
    model = load_model()
    params = make_params(model, tx_px=100, ty_px=100, scale_px=50, ry_rad=1.2)
    visible = visible_triangles(model, params)
    assert 0 < visible.sum() < len(model.triangles)


def test_projection_is_batched_and_geometric():
    model = load_model()
    p = make_params(model, tx_px=10, ty_px=20, scale_px=2)
    single = project(model, p)
    batch = project(model, np.stack([p, p]))
    assert np.allclose(batch[1], single)
    # Weak perspective, frontal: x = tx + s X, y = ty - s Y.
    assert np.allclose(single[:, 0], 10 + 2 * model.vertices[:, 0])
    assert np.allclose(single[:, 1], 20 - 2 * model.vertices[:, 1])
    # Roll by 90 degrees turns the model's +x to image +y... (y down: +x maps to -y image after roll)
    rolled = project(model, make_params(model, tx_px=0, ty_px=0, scale_px=1, rz_rad=np.pi / 2))
    assert np.allclose(rolled[:, 0], -model.vertices[:, 1], atol=1e-9)
    # Perspective magnifies the nearer nose tip more than the contour.
    near = project(model, p, focal_px=20.0)
    assert not np.allclose(near, single)


def test_candide3_loads(shared_data):
    model = read_wfm(shared_data / "faces" / "candide3" / "candide3.wfm")
    assert model.n_vertices == 113
    assert len(model.triangles) == 184
    assert model.n_actions > 10 and model.n_shapes > 10
    assert any("Jaw drop" in name for name in model.action_unit_names)


def test_candide3_loads_through_load_model(shared_data):
    assert load_model(shared_data / "faces" / "candide3" / "candide3.wfm").n_vertices == 113


@pytest.mark.parametrize(
    "text, message",
    [
        (
            "# VERTEX LIST:\n2\n0 0 0\n",
            "line 3 of .*unexpected end of file|line .*expected 'x y z'",
        ),
        ("# VERTEX LIST:\nabc\n", "line 2 of .*number of vertices"),
        ("# VERTEX LIST:\n3\n0 0 0\n1 0 x\n0 1 0\n", "line 4 of .*'x y z'"),
        (
            "# VERTEX LIST:\n3\n0 0 0\n1 0 0\n0 1 0\n# FACE LIST:\n1\n0 1\n",
            "line 8 of .*three vertex",
        ),
        ("nothing here\n", "no '# VERTEX LIST' section"),
    ],
)
def test_malformed_wfm_names_file_and_line(tmp_path, text, message):
    path = tmp_path / "bad.wfm"
    path.write_text(text)
    with pytest.raises(FaceError, match=message):
        read_wfm(path)


def test_missing_model_file(tmp_path):
    with pytest.raises(FaceError, match="no such"):
        load_model(tmp_path / "none.yaml")
