"""The face readers' refusals, one by one: FAP values and frame rates a face cannot have, point
names and duplicates, damaged description members, and points that lie on no detected face."""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest

from uma.errors import FaceError
from uma.face.detect import Box, face_of_points
from uma.face.fap import MAX_ANGLE_AU, MAX_DISTANCE_FAPU, FapSequence, parse_fap
from uma.face.npz import read_npz, write_npz
from uma.face.points import load_points, read_points

MASK = " ".join(["0", "0", "1"] + ["0"] * 44 + ["0", "1"] + ["0"] * 19)  # FAPs 3 and 49


def _fap(jaw: int, yaw: int, fps: str = "25") -> str:
    return f"2.1 probe {fps} 1\n# a comment\n{MASK}\n0 {jaw} {yaw}\n"


def test_fap_values_within_a_face_are_read():
    sequence = parse_fap(_fap(MAX_DISTANCE_FAPU, -MAX_ANGLE_AU), where="f.fap")
    assert sequence.frames == ({3: MAX_DISTANCE_FAPU, 49: -MAX_ANGLE_AU},)


@pytest.mark.parametrize(
    "jaw, yaw, message",
    [
        (MAX_DISTANCE_FAPU + 1, 0, r"f\.fap:4: FAP 3 \(open_jaw\): expected at most 4096 MNS"),
        (10**12, 0, r"f\.fap:4: FAP 3 .* got 1000000000000"),
        (0, -(MAX_ANGLE_AU + 1), r"f\.fap:4: FAP 49 \(head_yaw\): expected at most 314159 AU"),
        (0, 10**26, r"f\.fap:4: FAP 49"),
    ],
)
def test_fap_values_beyond_a_face_are_refused_with_the_line(jaw, yaw, message):
    with pytest.raises(FaceError, match=message):
        parse_fap(_fap(jaw, yaw), where="f.fap")
    with pytest.raises(FaceError, match="expected at most"):
        FapSequence(name="x", fps=25, frames=({3: jaw, 49: yaw},))


@pytest.mark.parametrize("fps", ["1e300", "0", "-25", "nan", "inf", "1e-9"])
def test_absurd_header_frame_rates_are_refused_with_the_line(fps):
    with pytest.raises(FaceError, match=rf"f\.fap:1: expected a frame rate of 0.01-1000 .*{fps}"):
        parse_fap(_fap(0, 0, fps), where="f.fap")


def test_point_names_keep_their_text_and_unknown_ones_are_refused(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text("points:\n  3.10: [1, 2]\n  3.1: [3, 4]\n")
    assert read_points(path) == {"3.10": (1.0, 2.0), "3.1": (3.0, 4.0)}  # not 3.1 twice
    path.write_text("points:\n  3.5: [1, 2]\n  '99.9': [3, 4]\n")
    with pytest.raises(FaceError, match=r"p\.yaml:3 \(points\['99\.9'\]\): expected an MPEG-4"):
        read_points(path)
    path.write_text("'3.5': [1, 2]\nleft_pupil: [3, 4]\n")
    with pytest.raises(FaceError, match=r"p\.yaml:2 \('left_pupil'\): .*\(2\.1-2\.14, 3\.1-3\.14"):
        read_points(path)


def test_duplicate_points_and_stray_keys_are_refused_with_lines(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text("points:\n  '3.5': [1, 2]\n  '3.6': [1, 2]\n  '3.5': [5, 6]\n")
    with pytest.raises(FaceError, match=r"p\.yaml:4 \(points\['3\.5'\]\): duplicate key, .* 2"):
        read_points(path)
    path.write_text("vidoe: a.mp4\npoints: {'3.5': [1, 2]}\n")
    with pytest.raises(FaceError, match=r"p\.yaml:1 \(vidoe\): expected one of points, video"):
        load_points(path)


def test_nan_points_name_their_line(tmp_path):
    path = tmp_path / "p.json"
    path.write_text('{"points": {\n "3.5": [1, 2],\n "3.6": [NaN, 2]\n}}\n')
    with pytest.raises(FaceError, match=r"p\.json:3 \(points\['3\.6'\]\): expected \[x, y\]"):
        read_points(path)


def _zip(members: dict[str, bytes]) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        for name, data in members.items():
            archive.writestr(name, data)
    return buffer.getvalue()


def test_description_members_are_checked_without_pickle(tmp_path):
    path = tmp_path / "d.face"
    path.write_bytes(write_npz(params=np.zeros(3)))
    with pytest.raises(FaceError, match=r"d\.face: expected .* got an archive without meta\.npy"):
        read_npz(path, what="a description", names=("params", "meta"))
    objects = io.BytesIO()
    np.save(objects, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    path.write_bytes(_zip({"params.npy": objects.getvalue()}))
    with pytest.raises(FaceError, match=r"d\.face: params: expected numbers, got dtype object"):
        read_npz(path, what="a description", names=("params",))
    # A header that claims more than the member holds is refused before any allocation.
    head = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        head, {"descr": "<f8", "fortran_order": False, "shape": (10**15,)}
    )
    path.write_bytes(_zip({"params.npy": b"\x93NUMPY\x01\x00" + head.getvalue()[8:]}))
    with pytest.raises(FaceError, match=r"params: expected 8000000000000000 bytes"):
        read_npz(path, what="a description", names=("params",))


def test_points_on_no_detected_face_are_refused_and_strays_warned():
    face = Box(100, 100, 100, 100)
    inside = {f"3.{k}": (110.0 + 10 * k, 130.0 + k) for k in range(1, 9)}
    box, warning = face_of_points([Box(0, 0, 30, 30), face], inside)
    assert box == face and warning is None
    one_off = dict(inside, **{"2.1": (150.0, 300.0)})  # the chin clicked on the chest
    box, warning = face_of_points([face], one_off)
    assert box == face and "1 of 9 points (2.1) lie away from the face detected" in warning
    elsewhere = {k: (x + 300, y + 200) for k, (x, y) in inside.items()}
    failure = face_of_points([face], elsewhere)
    assert not failure and "no detected face" in failure.reason
    tiny = {k: (150 + (x - 150) / 20, y) for k, (x, y) in inside.items()}
    assert "span" in face_of_points([face], tiny)[1]


def test_endless_and_oversized_inputs_are_refused(tmp_path, monkeypatch):
    import os

    import uma.face.npz
    from uma.face import load_description
    from uma.face.fap import read_fap

    if not os.path.exists("/dev/zero") or not hasattr(os, "mkfifo"):
        pytest.skip("no /dev/zero or FIFOs")
    endless = tmp_path / "z.yaml"
    endless.symlink_to("/dev/zero")
    with pytest.raises(FaceError, match=r"z\.yaml: expected .*\(a regular file\), got a character"):
        read_points(endless)
    # A FIFO with no writer: opening it would wait forever; refused before any read.
    fifo = tmp_path / "points.yaml"
    os.mkfifo(fifo)
    with pytest.raises(FaceError, match=r"points\.yaml: expected .*\(a regular file\), got a FIFO"):
        read_points(fifo)
    monkeypatch.setattr(uma.face.npz, "MAX_ARCHIVE_BYTES", 1000)
    big = tmp_path / "big.face"
    big.write_bytes(b"PK\x03\x04" + bytes(2000))
    with pytest.raises(FaceError, match=r"big\.face: 2004 bytes, above the maximum"):
        load_description(big)
    with pytest.raises(FaceError, match=r"expected a \.fap file \(a regular file\), got a folder"):
        read_fap(tmp_path)


def test_the_face_that_suits_the_points_is_chosen():
    big, small = Box(0, 0, 400, 400), Box(100, 100, 100, 100)
    points = {f"3.{k}": (115.0 + 9 * k, 140.0) for k in range(1, 9)}  # 63 px across
    box, warning = face_of_points([big, small], points)
    assert box == small and warning is None


def test_a_face_the_frontal_cascade_misses_is_still_a_face(shared_data):
    import cv2

    from uma.face.detect import detect_faces, locate_points
    from uma.face.landmarks import read_dlib_xml, to_mpeg4

    folder = shared_data / "faces" / "landmarks68"
    face = next(
        f
        for f in read_dlib_xml(folder / "training_with_face_landmarks.xml")
        if f.image == "2008_002079.jpg" and f.box[:2] == (122, 134)
    )
    gray = cv2.cvtColor(cv2.imread(str(folder / face.image)), cv2.COLOR_BGR2GRAY)
    points = to_mpeg4(face.landmarks)
    assert not face_of_points(detect_faces(gray), points)  # crowded: the default misses it
    box, warning = locate_points(gray, points)  # the other cascades find it
    assert warning is None and abs(box.x - 122) < 20 and abs(box.y - 134) < 20
