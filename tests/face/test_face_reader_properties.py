"""Every face-room reader, fed truncated, bit-flipped and foreign bytes: the one-line error or a
correct result, never another exception, a warning or a message over several lines.

Readers: content descriptions (`.face`), `.fap` files, points files (YAML and JSON), 68-point
`.pts` landmarks, dlib's landmark XML and uma's face model YAML (`--model`).
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest
import skimage.data
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uma.errors import UmaError
from uma.face import ContentDescription, describe, load_description, read_points
from uma.face.fap import FapSequence, fap_limit, format_fap, read_fap
from uma.face.landmarks import LandmarkFace, read_dlib_xml, read_pts
from uma.face.model import FaceModel, read_model_yaml
from uma.face.points import MPEG4_POINTS, load_points
from uma.paths import codecs_dir

ASTRONAUT = codecs_dir() / "face" / "astronaut.yaml"
SETTINGS = settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("hostile")


@pytest.fixture(scope="module")
def good_face() -> bytes:
    image = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    result = describe(image, read_points(ASTRONAUT))
    assert isinstance(result, ContentDescription)
    return result.to_bytes()


def _good_fap() -> bytes:
    frames = ({3: 120, 48: -5000, 19: 1024}, {}, {3: -4096, 50: 314159})
    return format_fap(FapSequence(name="probe", fps=25.0, frames=frames)).encode()


def _good_points_json() -> bytes:
    return json.dumps({"points": read_points(ASTRONAUT)}, indent="\t").encode()


def _good_pts() -> bytes:
    rng = np.random.default_rng(1)
    xy = rng.uniform(10, 200, (68, 2))
    body = "\n".join(f"{x:.3f} {y:.3f}" for x, y in xy)
    return f"version: 1\nn_points: 68\n{{\n{body}\n}}\n".encode()


def _good_xml() -> bytes:
    rng = np.random.default_rng(2)
    parts = "".join(
        f"<part name='{k:02d}' x='{x:.0f}' y='{y:.0f}'/>"
        for k, (x, y) in enumerate(rng.uniform(10, 90, (68, 2)))
    )
    return (
        "<?xml version='1.0' encoding='ISO-8859-1'?>\n<dataset><images>\n"
        f"<image file='a.jpg'>\n<box top='5' left='5' width='90' height='90'>{parts}</box>\n"
        "</image>\n</images></dataset>\n"
    ).encode()


FOREIGN = [
    b"",
    b"\x00" * 32,
    b"\xff\xd8\xff\xe0\x00\x10JFIF\x00",  # a JPEG's first bytes
    b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR",
    b"PK\x03\x04" + b"\x00" * 26,  # a zip header and nothing behind it
    b"\x93NUMPY\x01\x00v\x00{'descr': '|O', 'fortran_order': False, 'shape': (3,), }",
    b"version: 1\nn_points: 99999999999\n{\n",
    b"2.1 x 1e300 1\n",
    ("2.1 x 25 1\n" + " ".join(["0", "0", "1"] + ["0"] * 65) + "\n0 1000000000000\n").encode(),
    b"<?xml version='1.0' encoding='HSO-8859-1'?><dataset/>",
    b"points: {'3.5': [.nan, 1]}\n",
    b"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[",
    "caf\u00e9: \u2603\n".encode(),
    b"<dataset><images><image file='a.jpg'><box top='1e9'/></image></images></dataset>",
]


def hostile(good: bytes) -> st.SearchStrategy[bytes]:
    """Bytes of `good` truncated, with a few bits flipped, or bytes of something else."""

    def flip(changes: list[tuple[int, int]]) -> bytes:
        out = bytearray(good)
        for position, bit in changes:
            out[position % len(out)] ^= 1 << bit
        return bytes(out)

    truncated = st.integers(0, len(good) - 1).map(lambda n: good[:n])
    flipped = st.lists(
        st.tuples(st.integers(0, len(good) - 1), st.integers(0, 7)), min_size=1, max_size=4
    ).map(flip)
    foreign = st.sampled_from(FOREIGN) | st.binary(max_size=64)
    return st.one_of(truncated, flipped, foreign)


def one_line_or_result(path: Path, read: Callable[[Path], Any], check: Callable[[Any], None]):
    """`read(path)` returns a result `check` accepts, or raises an `UmaError` of one line that
    names the file; no other exception, and no warning on the way."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            result = read(path)
        except UmaError as err:
            message = str(err)
            assert message and "\n" not in message and "\r" not in message, message
            assert path.name in message, message
            assert "pickle" not in message, message
            return
    check(result)


def _check_description(d: ContentDescription) -> None:
    assert isinstance(d, ContentDescription) and isinstance(d.model, FaceModel)
    for array in (d.params, d.shape, d.model.vertices, d.model.action_units):
        assert np.all(np.isfinite(array))
    assert d.params.shape == (6 + d.model.n_actions,) and d.texture.ndim in (2, 3)


def _check_fap(sequence: FapSequence) -> None:
    assert 0.01 <= sequence.fps <= 1000
    assert all(abs(v) <= fap_limit(k) for f in sequence.frames for k, v in f.items())


def _check_points(points: dict) -> None:
    assert points and set(points) <= MPEG4_POINTS
    assert np.all(np.isfinite(np.array(list(points.values()))))


def _check_mapped(points: dict) -> None:
    """Landmarks mapped to MPEG-4 points: a point whose landmarks are absent is left out."""
    assert set(points) <= MPEG4_POINTS
    assert all(np.isfinite(xy).all() for xy in points.values())


def _check_pts(xy: np.ndarray) -> None:
    assert xy.ndim == 2 and xy.shape[1] == 2 and np.all(np.isfinite(xy))


def _check_model(model: FaceModel) -> None:
    assert isinstance(model, FaceModel) and np.all(np.isfinite(model.vertices))


def _check_picture(image: np.ndarray) -> None:
    assert image.ndim == 3 and image.shape[2] == 3 and image.dtype == np.uint8


def _check_xml(faces: list) -> None:
    assert all(isinstance(f, LandmarkFace) and f.landmarks.shape == (68, 2) for f in faces)


@SETTINGS
@given(data=st.data())
def test_descriptions(folder, good_face, data):
    path = folder / "d.face"
    path.write_bytes(data.draw(hostile(good_face)))
    one_line_or_result(path, load_description, _check_description)


@SETTINGS
@given(content=hostile(_good_fap()))
def test_fap_files(folder, content):
    path = folder / "a.fap"
    path.write_bytes(content)
    one_line_or_result(path, read_fap, _check_fap)


@SETTINGS
@given(content=hostile(ASTRONAUT.read_bytes()))
def test_points_yaml(folder, content):
    path = folder / "p.yaml"
    path.write_bytes(content)
    one_line_or_result(path, lambda p: load_points(p).points, _check_points)


@SETTINGS
@given(content=hostile(_good_points_json()))
def test_points_json(folder, content):
    path = folder / "p.json"
    path.write_bytes(content)
    one_line_or_result(path, read_points, _check_points)


@SETTINGS
@given(content=hostile(_good_pts()))
def test_pts_landmarks(folder, content):
    path = folder / "l.pts"
    path.write_bytes(content)
    one_line_or_result(path, read_pts, _check_pts)
    one_line_or_result(path, lambda p: load_points(p).points, _check_mapped)


@SETTINGS
@given(content=hostile(_good_xml()))
def test_dlib_xml_landmarks(folder, content):
    path = folder / "l.xml"
    path.write_bytes(content)
    one_line_or_result(path, read_dlib_xml, _check_xml)
    one_line_or_result(path, lambda p: load_points(p, image="a.jpg").points, _check_mapped)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_model_yaml(folder, data):
    whole = (codecs_dir() / "face" / "uma-face.yaml").read_bytes()
    path = folder / "m.yaml"
    path.write_bytes(data.draw(hostile(whole[:2500])))  # a head of it: damaged already
    one_line_or_result(path, read_model_yaml, _check_model)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_candide3_wfm_models(folder, shared_data, data):
    from uma.face.wfm import read_wfm

    whole = (shared_data / "faces" / "candide3" / "candide3.wfm").read_bytes()
    path = folder / "m.wfm"
    path.write_bytes(data.draw(hostile(whole)))
    one_line_or_result(path, read_wfm, _check_model)


def _good_picture(kind: str) -> bytes:
    rng = np.random.default_rng(4)
    picture = rng.integers(0, 255, (24, 32, 3), dtype=np.uint8)
    return cv2.imencode(f".{kind}", picture)[1].tobytes()


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), kind=st.sampled_from(["jpg", "png"]))
def test_pictures(folder, data, kind):
    from uma.face.clip import read_picture

    path = folder / f"p.{kind}"
    path.write_bytes(data.draw(hostile(_good_picture(kind))))
    one_line_or_result(path, read_picture, _check_picture)
