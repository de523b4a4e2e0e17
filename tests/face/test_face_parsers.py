"""Property tests for the face file readers: any input gives a model or a FaceError."""

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uma.errors import FaceError
from uma.face import read_points, read_wfm

coordinate = st.floats(-2, 2, allow_nan=False).map(lambda v: round(v, 4))


@st.composite
def wfm_text(draw):
    n = draw(st.integers(3, 12))
    vertices = [[draw(coordinate) for _ in range(3)] for _ in range(n)]
    triangles = draw(st.lists(st.tuples(*[st.integers(0, n - 1)] * 3), min_size=1, max_size=10))
    units = draw(
        st.lists(
            st.lists(
                st.tuples(st.integers(0, n - 1), coordinate, coordinate, coordinate), max_size=4
            ),
            max_size=3,
        )
    )
    lines = ["# generated", "", "# VERTEX LIST:", str(n)]
    lines += [" ".join(f"{v:.4f}" for v in row) for row in vertices]
    lines += ["", "# FACE LIST:", str(len(triangles))]
    lines += [" ".join(map(str, t)) for t in triangles]
    lines += ["", "# ANIMATION UNITS LIST:", str(len(units))]
    for k, unit in enumerate(units):
        lines += ["", f"# FAP{k + 3} unit {k}", "# MNS", str(len(unit))]
        lines += [f"{i} {dx} {dy} {dz}" for i, dx, dy, dz in unit]
    lines += ["", "# SHAPE UNITS LIST:", "0", "# END OF FILE"]
    return "\n".join(lines) + "\n", np.array(vertices), len(triangles), units


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(case=wfm_text())
def test_wellformed_wfm_round_trips(tmp_path, case):
    text, vertices, n_triangles, units = case
    path = tmp_path / "g.wfm"
    path.write_text(text)
    model = read_wfm(path)
    assert np.allclose(model.vertices, vertices)
    assert len(model.triangles) == n_triangles
    assert model.action_unit_names == tuple(f"FAP{k + 3} unit {k}" for k in range(len(units)))
    for k, unit in enumerate(units):
        for i, dx, dy, dz in unit[-1:]:
            assert np.allclose(model.action_units[k, i], [dx, dy, dz])


@settings(
    max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(text=st.text(max_size=300), cut=st.integers(0, 400))
def test_damaged_wfm_is_a_face_error(tmp_path, text, cut):
    good = "# VERTEX LIST:\n3\n0 0 0\n1 0 0\n0 1 0\n# FACE LIST:\n1\n0 1 2\n"
    good += "# ANIMATION UNITS LIST:\n0\n# SHAPE UNITS LIST:\n0\n"
    path = tmp_path / "d.wfm"
    path.write_text(good[:cut] + text + good[cut:], encoding="utf-8")
    try:
        read_wfm(path)
    except FaceError as err:
        assert "d.wfm" in str(err)


@settings(
    max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    data=st.recursive(
        st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
        lambda inner: (
            st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner, max_size=3)
        ),
        max_leaves=8,
    )
)
def test_any_point_file_gives_points_or_a_face_error(tmp_path, data):
    import json

    path = tmp_path / "p.json"
    path.write_text(json.dumps(data))
    try:
        points = read_points(path)
    except FaceError as err:
        assert "p.json" in str(err)
        return
    assert points and all(np.isfinite(v).all() and len(v) == 2 for v in points.values())
