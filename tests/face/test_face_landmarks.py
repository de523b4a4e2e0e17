"""68-point iBUG landmarks (.pts, dlib XML) as MPEG-4 feature points."""

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.cli import main
from uma.errors import FaceError
from uma.face import fit_points, load_description, project
from uma.face.landmarks import (
    IBUG68_TO_MPEG4,
    N_LANDMARKS,
    parse_pts,
    read_dlib_xml,
    read_pts,
    to_mpeg4,
)
from uma.face.points import load_points

coords = st.floats(min_value=-1e4, max_value=1e4, allow_nan=False, allow_infinity=False)


def _pts_text(points, *, blank_lines=0):
    lines = ["version: 1", f"n_points: {len(points)}", "{"]
    lines += [f"{float(x)!r} {float(y)!r}" for x, y in points]
    lines += ["}"] + [""] * blank_lines
    return "\n".join(lines) + "\n"


@given(st.lists(st.tuples(coords, coords), min_size=1, max_size=80), st.integers(0, 3))
def test_pts_round_trip(points, blank_lines):
    parsed = parse_pts(_pts_text(points, blank_lines=blank_lines), one_based=False)
    assert parsed.shape == (len(points), 2)
    assert np.array_equal(parsed, np.array(points, dtype=np.float64))
    assert np.array_equal(parse_pts(_pts_text(points)), parsed - 1.0)  # 1-based by default


BAD_LINES = ["1.0", "1 2 3", "x y", "nan 2", "1 inf", "{", "version: 1", "1,2"]


@settings(max_examples=150)
@given(
    st.lists(st.tuples(coords, coords), min_size=2, max_size=20),
    st.data(),
    st.sampled_from(BAD_LINES),
)
def test_a_malformed_line_is_named(points, data, bad):
    lines = _pts_text(points).splitlines()
    number = data.draw(st.integers(1, len(lines)), label="line")
    line = lines[number - 1]
    if bad == "{" and line == "{" or bad == "version: 1" and number == 1:
        return  # the replacement is what the line must be
    lines[number - 1] = bad
    with pytest.raises(FaceError) as error:
        parse_pts("\n".join(lines) + "\n", where="face.pts")
    assert f"face.pts:{number}:" in str(error.value)
    assert isinstance(error.value, ValueError)


@given(st.lists(st.tuples(coords, coords), min_size=1, max_size=10), st.integers(0, 2))
def test_too_few_or_extra_lines_are_named(points, cut):
    lines = _pts_text(points).splitlines()
    short = "\n".join(lines[: len(lines) - 1 - cut])
    with pytest.raises(FaceError, match=r"face\.pts:\d+: expected"):
        parse_pts(short, where="face.pts")
    with pytest.raises(FaceError, match=rf"face\.pts:{len(lines) + 1}: expected the end"):
        parse_pts("\n".join(lines + ["3 4"]), where="face.pts")


def test_read_pts_missing_file(tmp_path):
    with pytest.raises(FaceError, match="no such landmark file"):
        read_pts(tmp_path / "none.pts")


def test_mapping_covers_model_points_with_valid_landmarks(face_model):
    model = face_model
    for name, indices in IBUG68_TO_MPEG4.items():
        assert name in model.feature_points, name
        assert indices and all(0 <= i < N_LANDMARKS for i in indices)
    # Odd MPEG-4 numbers are the subject's left: iBUG's higher-numbered side (the viewer's right).
    assert IBUG68_TO_MPEG4["3.7"] == (45,) and IBUG68_TO_MPEG4["3.8"] == (36,)


def _ibug_like(model, params):
    """68 landmarks placed where the model puts the MPEG-4 points they map to (one landmark
    per single-point entry; the means of multi-point entries made exact)."""
    xy = project(model, params)
    landmarks = np.full((N_LANDMARKS, 2), np.nan)
    for name, indices in IBUG68_TO_MPEG4.items():
        target = xy[model.feature_points[name]]
        if len(indices) == 1:
            landmarks[indices[0]] = target
    for name, indices in sorted(IBUG68_TO_MPEG4.items(), key=lambda item: len(item[1])):
        target = xy[model.feature_points[name]]
        if len(indices) > 1:
            free = [i for i in indices if np.isnan(landmarks[i, 0])]
            if not free:
                continue  # a pupil: the mean of its eye's corners and lids, as given
            fixed = [i for i in indices if i not in free]
            rest = len(indices) * target - landmarks[fixed].sum(axis=0)
            landmarks[free] = rest / len(free)
    return landmarks


def test_landmarks_where_the_model_puts_them_fit_the_pose(face_model):
    model = face_model
    params = np.array([200.0, 150.0, 60.0, 0.05, -0.1, 0.08] + [0.0] * model.n_actions)
    landmarks = _ibug_like(model, params)
    landmarks[np.isnan(landmarks)] = 0.0  # landmarks the mapping does not use
    points = to_mpeg4(landmarks)
    fit = fit_points(model, points, fit_shape=False, fit_actions=False)
    # Exact but for the pupils, which are the mean of their eye's six landmarks.
    assert fit and fit.rms_px < 0.005 * params[2]
    assert np.allclose(fit.params[:3], params[:3], atol=0.5)
    assert np.allclose(fit.params[3:6], params[3:6], atol=0.02)


def test_absent_parts_leave_their_points_out():
    landmarks = np.zeros((N_LANDMARKS, 2))
    landmarks[44] = np.nan
    points = to_mpeg4(landmarks)
    assert "3.5" not in points and "3.1" not in points and "3.3" in points


def test_dlib_xml_errors(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text("<dataset><images><image file='a.jpg'>\n<box top='1'>\n</images>")
    with pytest.raises(FaceError, match=r"bad\.xml:\d+: not well-formed XML"):
        read_dlib_xml(bad)
    part = tmp_path / "part.xml"
    part.write_text(
        "<dataset><images><image file='a.jpg'><box top='1' left='2' width='3' height='4'>"
        "<part name='70' x='1' y='2'/></box></image></images></dataset>"
    )
    with pytest.raises(FaceError, match=r"a\.jpg box 0: part '70'"):
        read_dlib_xml(part)
    part.write_text(part.read_text().replace("'70'", "'07'"))
    assert len(read_dlib_xml(part)) == 1
    with pytest.raises(FaceError, match="no face annotated for b.jpg"):
        load_points(part, image="b.jpg")


@pytest.fixture(scope="module")
def dlib_files(shared_data):
    folder = shared_data / "faces" / "landmarks68"
    return folder, [folder / f"{n}_with_face_landmarks.xml" for n in ("training", "testing")]


def test_reads_the_shared_dlib_files(dlib_files, face_model):
    _, files = dlib_files
    faces = [face for path in files for face in read_dlib_xml(path)]
    assert len(faces) == 43
    assert all(np.isfinite(face.landmarks).all() for face in faces)
    # Every annotated face fits the model through the mapping, without a click by hand.
    model = face_model
    for face in faces:
        fit = fit_points(model, to_mpeg4(face.landmarks))
        assert fit, (face.image, fit.reason)
        assert fit.rms_px < 0.04 * fit.params[2], face.image  # under 4 % of the face's scale


def test_cli_describes_a_dlib_photo(dlib_files, tmp_path, capsys):
    folder, files = dlib_files
    image = folder / "2008_002506.jpg"
    assert main(["describe", str(image), "--points", str(files[1]), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    rms = float(re.search(r"fitted to ([\d.]+) px rms", out).group(1))
    description = load_description(tmp_path / "2008_002506.face")
    assert description.fit_rms_px == pytest.approx(rms, abs=0.01)
    assert rms < 3.0  # the largest of its three faces, 109 px box
    # Another face of the same photo by --face, and a face that is not there.
    args = ["describe", str(image), "--points", str(files[1]), "--out", str(tmp_path / "b")]
    assert main([*args, "--face", "1"]) == 0
    assert main([*args, "--face", "3"]) == 2
    assert "has 3 annotated faces" in capsys.readouterr().err


def test_pts_through_the_cli(dlib_files, tmp_path, capsys):
    folder, files = dlib_files
    face = max(
        (f for f in read_dlib_xml(files[1]) if f.image == "2008_002506.jpg"),
        key=lambda f: f.box[2],
    )
    pts = tmp_path / "2008_002506.pts"
    pts.write_text(_pts_text([(x + 1, y + 1) for x, y in face.landmarks]))  # .pts is 1-based
    image = folder / "2008_002506.jpg"
    assert main(["describe", str(image), "--points", str(pts), "--out", str(tmp_path)]) == 0
    from_pts = load_description(tmp_path / "2008_002506.face")
    assert main(["describe", str(image), "--points", str(files[1]), "--out", str(tmp_path)]) == 0
    from_xml = load_description(tmp_path / "2008_002506.face")
    assert from_pts.fit_rms_px == pytest.approx(from_xml.fit_rms_px, abs=1e-9)
    wrong = tmp_path / "short.pts"
    wrong.write_text(_pts_text([(1.0, 2.0)] * 5))
    assert main(["describe", str(image), "--points", str(wrong)]) == 2
    assert "68-point" in capsys.readouterr().err
