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


def test_wireframe_has_what_the_codec_needs(face_model):
    model = face_model
    assert 100 <= len(model.triangles) <= 200
    for unit in ("jaw_drop", "lip_stretch", "lip_corner_depressor", "brow_raise", "eye_close"):
        assert unit in model.action_unit_names
    assert {"3.5", "3.6", "9.3", "8.3", "8.4", "2.1"} <= set(model.feature_points)
    # Every triangle faces the camera in the frontal pose (consistent winding).
    params = make_params(model, tx_px=100, ty_px=100, scale_px=50)
    assert visible_triangles(model, params).all()


def test_units_bend_the_mesh_without_folding_it(face_model):
    model = face_model
    frontal = make_params(model, tx_px=0, ty_px=0, scale_px=100)
    for k in range(model.n_shapes):
        for value in (-1.0, 1.0):
            shape = np.zeros(model.n_shapes)
            shape[k] = value
            person = model.personalised(shape)
            assert visible_triangles(person, frontal).all(), model.shape_unit_names[k]
    for k in range(model.n_actions):
        for value in np.linspace(0.0, 1.0, 6):
            actions = np.zeros(model.n_actions)
            actions[k] = value
            params = make_params(model, tx_px=0, ty_px=0, scale_px=100, actions=actions)
            assert visible_triangles(model, params).all(), model.action_unit_names[k]
    everything = make_params(
        model, tx_px=0, ty_px=0, scale_px=100, actions=np.ones(model.n_actions)
    )
    assert visible_triangles(model, everything).all()


def test_wireframe_is_mirror_symmetric(face_model):
    model = face_model
    mirrored = model.vertices * np.array([-1.0, 1.0, 1.0])
    # Each vertex has a mirror twin, and each triangle a mirrored twin.
    distance = np.linalg.norm(mirrored[:, None] - model.vertices[None], axis=2)
    twin = distance.argmin(axis=1)
    assert np.allclose(distance.min(axis=1), 0, atol=1e-6)
    triangles = {tuple(sorted(t)) for t in model.triangles.tolist()}
    assert {tuple(sorted(twin[list(t)])) for t in triangles} == triangles


def test_turning_away_culls_triangles(face_model):
    model = face_model
    params = make_params(model, tx_px=100, ty_px=100, scale_px=50, ry_rad=1.2)
    visible = visible_triangles(model, params)
    assert 0 < visible.sum() < len(model.triangles)


def test_projection_is_batched_and_geometric(face_model):
    model = face_model
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
    # A unit's name is its first comment line, not the FAP unit on the second.
    assert "FAP 3 open_jaw" in model.action_unit_names
    assert not {"MNS", "MW", "ENS", "ES", "IRISD"} & set(model.action_unit_names)
    assert "Head height" in model.shape_unit_names
    # Wound counter-clockwise from the front, like uma's own: nothing culled when frontal.
    assert visible_triangles(model, make_params(model, tx_px=0, ty_px=0, scale_px=100)).all()


def test_candide3_feature_points_come_from_its_faps(shared_data):
    model = read_wfm(shared_data / "faces" / "candide3" / "candide3.wfm")
    points = model.feature_points
    v = model.vertices
    assert len(points) >= 30
    assert points["2.1"] == int(np.argmin(v[:, 1]))  # bottom of the chin
    assert points["9.3"] == int(np.argmax(v[:, 2]))  # nose tip, nearest the camera
    assert v[points["3.7"], 0] > v[points["3.11"], 0] > 0 > v[points["3.12"], 0]  # left is +x
    assert v[points["8.3"], 0] > 0 > v[points["8.4"], 0]
    assert v[points["4.1"], 1] > v[points["3.1"], 1] > v[points["3.3"], 1]  # brow, lids
    override = read_wfm(
        shared_data / "faces" / "candide3" / "candide3.wfm", feature_points={"3.5": 3}
    )
    assert override.feature_points["3.5"] == 3 and override.feature_points["2.1"] == points["2.1"]


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
        (
            "# VERTEX LIST:\n3\n0 0 0\n1 0 0\n0 1 0\n# FACE LIST:\n1\n0 1 2\n"
            "# ANIMATION UNITS LIST:\n1\n# jaw\n1\n7 0 1 0\n",
            "line 13 of .*vertex 7 outside 0-2",
        ),
        (
            "# VERTEX LIST:\n3\n0 0 0\n1 0 0\n0 1 0\n# FACE LIST:\n1\n0 1 2\n"
            "# ANIMATION UNITS LIST:\n0\n",
            "no '# SHAPE UNITS LIST' section",
        ),
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


def test_load_model_reads_a_file_again_once_it_changed(tmp_path):
    from uma.face import load_model
    from uma.face.model import default_model_path

    path = tmp_path / "model.yaml"
    text = default_model_path().read_text()
    path.write_text(text)
    first = load_model(path)
    assert load_model(path) is first  # read once
    path.write_text(text + "\n# edited\n")  # another size: the file changed
    again = load_model(path)
    assert again is not first and np.array_equal(again.vertices, first.vertices)
