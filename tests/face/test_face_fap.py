"""MPEG-4 FBA .fap files and the FAP <-> model parameter mapping."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.errors import FaceError
from uma.face import describe_clip
from uma.face.fap import FAP_NAMES, N_FAPS, FapSequence, format_fap, parse_fap, read_fap, write_fap
from uma.face.fap_map import (
    FAP_TABLE,
    fap_matrix,
    fap_units,
    faps_to_parameters,
    parameters_to_faps,
)
from uma.face.geometry import N_POSE
from uma.paths import codecs_dir

SHARED_FAPS = ("anger", "beg", "disgust", "fear", "happy-for", "hate", "joy", "pride")

fap_frame = st.dictionaries(
    st.integers(1, N_FAPS), st.integers(-4096, 4096), min_size=0, max_size=N_FAPS
)
sequences = st.builds(
    FapSequence,
    name=st.text(st.characters(min_codepoint=33, max_codepoint=126), min_size=1, max_size=12),
    fps=st.sampled_from([25.0, 30.0, 12.5, 29.97]),
    frames=st.lists(fap_frame, min_size=0, max_size=6).map(tuple),
)


@pytest.fixture(scope="module")
def person():
    """The astronaut's personal model (shape units baked in) and its FAPUs."""
    model = describe_clip(codecs_dir() / "face" / "astronaut.yaml").model
    return model, fap_units(model)


def test_names_cover_the_68_faps():
    assert len(FAP_NAMES) == N_FAPS
    assert FAP_NAMES[3] == "open_jaw" and FAP_NAMES[48] == "head_pitch"
    assert FAP_NAMES[19] == "close_t_l_eyelid" and FAP_NAMES[68] == "pull_r_ear"
    assert all(k in FAP_NAMES for k in FAP_TABLE)


@pytest.mark.parametrize("name", SHARED_FAPS)
def test_reads_the_shared_files(shared_data, tmp_path, name):
    path = shared_data / "faces" / "fap" / f"{name}.fap"
    sequence = read_fap(path)
    header = path.read_text(encoding="latin-1").splitlines()[0].split()
    assert len(sequence) == int(header[-1]) and sequence.fps == 25.0
    assert sequence.version == "2.1" and sequence.name.endswith("TempFile")
    assert sequence.numbers == tuple(range(len(sequence)))
    assert all(1 not in f and 2 not in f for f in sequence.frames)
    assert all(48 in f and 3 in f for f in sequence.frames)
    # Written and read back: the same sequence, exactly.
    write_fap(sequence, tmp_path / "copy.fap")
    assert read_fap(tmp_path / "copy.fap") == sequence


def test_shared_files_drive_the_model_in_range(shared_data, person):
    model, units = person
    for name in SHARED_FAPS:
        sequence = read_fap(shared_data / "faces" / "fap" / f"{name}.fap")
        params = np.array([faps_to_parameters(f, model, units) for f in sequence.frames])
        assert np.all(np.isfinite(params))
        assert np.abs(params[:, 3:6]).max() < 0.1  # head turns of a few degrees
        assert np.abs(params[:, N_POSE:]).max() < 2.0  # within the units' fitted range


@settings(max_examples=60)
@given(sequences)
def test_round_trip_exact(sequence):
    assert parse_fap(format_fap(sequence)) == sequence


def test_comments_and_blank_lines_are_skipped():
    text = "# made by hand\n2.1 two words 25 1\n\n# mask\n" + "1 " * 3 + "0 " * 65 + "\n7 1 -2 3\n"
    sequence = parse_fap(text)
    assert sequence.name == "two words" and sequence.numbers == (7,)
    assert sequence.frames == ({1: 1, 2: -2, 3: 3},)


def _corrupt(kind: str, line: str) -> str:
    fields = line.split()
    if kind == "drop":
        return " ".join(fields[:-1]) if len(fields) > 1 else "x"
    if kind == "add":
        return line + " 1"
    if kind == "word":
        return " ".join(fields[:-1] + ["abc"])
    if kind == "float":
        return " ".join(fields[:-1] + ["1.5"])
    return "2"  # a flag or a count where it does not belong


@settings(max_examples=150)
@given(
    sequences.filter(lambda s: len(s) > 0),
    st.data(),
    st.sampled_from(["drop", "add", "word", "float", "two"]),
)
def test_a_malformed_line_is_named(sequence, data, kind):
    lines = format_fap(sequence).splitlines()
    number = data.draw(st.integers(2, len(lines)), label="line")
    changed = _corrupt(kind, lines[number - 1])
    is_mask = number % 2 == 0
    if not is_mask and kind == "two" and len(lines[number - 1].split()) == 1:
        return  # "2" is a valid value line for a frame without FAPs (a new frame number)
    lines[number - 1] = changed
    with pytest.raises(FaceError) as error:
        parse_fap("\n".join(lines) + "\n", where="clip.fap")
    assert f"clip.fap:{number}:" in str(error.value)
    assert isinstance(error.value, ValueError)


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "clip.fap:1: expected the header"),
        ("2.1 name 25\n", "clip.fap:1: expected the header"),
        ("2.1 name -25 0\n", "clip.fap:1: expected a frame rate"),
        ("2.1 name 25 2\n" + "0 " * 68 + "\n0\n", "clip.fap:3: the header says 2 frames"),
        ("2.1 name 25 1\n" + "0 " * 68 + "\n", "clip.fap:2: a mask line without its value"),
    ],
)
def test_header_and_count_errors(text, message):
    with pytest.raises(FaceError, match=message):
        parse_fap(text, where="clip.fap")


def test_missing_file(tmp_path):
    with pytest.raises(FaceError, match="no such .fap file"):
        read_fap(tmp_path / "none.fap")


def test_units_are_neutral_distances_over_1024(face_model):
    model = face_model
    units = fap_units(model)
    pupils = model.vertices[[model.feature_points["3.5"], model.feature_points["3.6"]]]
    assert units.es == pytest.approx(np.linalg.norm(pupils[0] - pupils[1]) / 1024)
    corners = model.vertices[[model.feature_points["8.3"], model.feature_points["8.4"]]]
    assert units.mw == pytest.approx(np.linalg.norm(corners[0] - corners[1]) / 1024)
    assert units.au == 1e-5
    assert all(v > 0 for v in units.by_name.values())


def test_signs_follow_the_fap_directions(person):
    model, units = person
    names = model.action_unit_names
    base = np.zeros(N_POSE + model.n_actions)

    def faps_of(**actions):
        params = base.copy()
        for name, value in actions.items():
            params[N_POSE + names.index(name)] = value
        return parameters_to_faps(params, model, units)

    assert faps_of(jaw_drop=0.5)[3] > 0  # open_jaw
    assert faps_of(eye_close=0.5)[19] > 0 and faps_of(eye_close=0.5)[20] > 0
    raised = faps_of(brow_raise=0.5)
    assert all(raised[k] > 0 for k in range(31, 37))
    stretched = faps_of(lip_stretch=0.5)
    assert stretched[6] > 0 and stretched[7] > 0 and stretched[6] == stretched[7]
    smile = faps_of(lip_corner_raiser=0.5)
    assert smile[12] > 0 and smile[13] > 0 and smile[59] > 0
    turned = base.copy()
    turned[3:6] = [0.01, -0.02, 0.03]
    assert {k: parameters_to_faps(turned, model, units)[k] for k in (48, 49, 50)} == {
        48: 1000,
        49: -2000,
        50: 3000,
    }


@settings(max_examples=80, deadline=None)
@given(
    st.lists(st.floats(-1.0, 1.0), min_size=7, max_size=7),
    st.lists(st.floats(-0.3, 0.3), min_size=3, max_size=3),
)
def test_fap_parameter_fap_round_trip_within_a_quantum(person, actions, angles):
    model, units = person
    params = np.concatenate([[0.0, 0.0, 1.0], angles, actions])
    faps = parameters_to_faps(params, model, units)
    back = faps_to_parameters(faps, model, units)
    # FAPs -> parameters -> FAPs: each FAP within one step of its value.
    again = parameters_to_faps(back, model, units)
    assert max(abs(again[k] - faps[k]) for k in faps) <= 1
    # Parameters -> FAPs -> parameters: within what rounding to whole FAPUs can move them.
    assert np.allclose(back[3:6], params[3:6], atol=0.5 * units.au + 1e-12)
    numbers, matrix = fap_matrix(model, units)
    scale = np.array([units.by_name[FAP_TABLE[k][3]] for k in numbers])
    solve = np.linalg.pinv(matrix * scale[:, None]) * scale[None, :]
    bound = 0.5 * np.abs(solve).sum(axis=1)
    assert np.all(np.abs(back[N_POSE:] - params[N_POSE:]) <= bound + 1e-9)
    assert bound.max() < 0.02  # a FAPU step is a small fraction of a unit's range


def test_base_is_where_faps_are_measured_from(person):
    model, units = person
    base = np.concatenate([[100.0, 80.0, 50.0, 0.1, 0.0, -0.05], np.full(model.n_actions, 0.2)])
    assert all(v == 0 for v in parameters_to_faps(base, model, units, base=base).values())
    moved = faps_to_parameters({48: 2000, 3: 300}, model, units, base=base)
    assert np.allclose(moved[:3], base[:3]) and moved[3] == pytest.approx(0.12)
    jaw = N_POSE + model.action_unit_names.index("jaw_drop")
    assert moved[jaw] > base[jaw]
    # An action unit no given FAP moves keeps its base value.
    brow = N_POSE + model.action_unit_names.index("brow_raise")
    assert moved[brow] == pytest.approx(base[brow])


def test_bad_sequences():
    with pytest.raises(FaceError, match="FAP 69"):
        FapSequence(name="x", fps=25, frames=({69: 1},))
    with pytest.raises(FaceError, match="expected a frame rate of 0.01-1000"):
        FapSequence(name="x", fps=0, frames=())
    with pytest.raises(FaceError, match="one-line"):
        FapSequence(name="a\nb", fps=25, frames=())


def test_a_track_becomes_a_fap_file_and_back(person, tmp_path):
    from uma.face.fap_map import fap_sequence

    model, units = person
    rng = np.random.default_rng(3)
    base = np.concatenate([[100.0, 80.0, 50.0, 0.0, 0.0, 0.0], np.zeros(model.n_actions)])
    track = np.repeat(base[None], 5, axis=0)
    track[:, 3:] += rng.uniform(-0.2, 0.2, (5, 3 + model.n_actions))
    sequence = fap_sequence(track, model, units, fps=25, name="track", base=base)
    write_fap(sequence, tmp_path / "track.fap")
    back = read_fap(tmp_path / "track.fap")
    assert back == sequence and len(back) == 5
    replayed = np.array([faps_to_parameters(f, model, units, base=base) for f in back.frames])
    assert np.abs(replayed[:, 3:6] - track[:, 3:6]).max() <= 0.5e-5 + 1e-12
    assert np.abs(replayed[:, N_POSE:] - track[:, N_POSE:]).max() < 0.02
