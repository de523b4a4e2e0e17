"""Hostile input files through every reader the command line has: one line, exit 2.

Issue 20's reader items: corrupt `.face` descriptions (7 ways) through `uma bench mbc --face`
and `engine.mbc.description` in a scenario, absurd FAP values and frame rates through
`uma source synth --fap`, points and model files that are truncated, unknown or misplaced
through `uma describe`, and a points file with `frame:` but no `video:`.
"""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest
import skimage.data
import yaml

from uma.cli import main
from uma.face import ContentDescription, describe, read_points
from uma.face.npz import write_npz
from uma.paths import codecs_dir

ASTRONAUT = codecs_dir() / "face" / "astronaut.yaml"
MASK_JAW = " ".join(["0", "0", "1"] + ["0"] * 65)  # FAP 3 (open_jaw) only


@pytest.fixture(scope="module")
def good_face(tmp_path_factory) -> bytes:
    """The astronaut's content description, as `uma describe` writes it."""
    image = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    result = describe(image, read_points(ASTRONAUT))
    assert isinstance(result, ContentDescription)
    return result.to_bytes()


def _arrays(good: bytes, tmp_path) -> dict[str, np.ndarray]:
    (tmp_path / "g.face").write_bytes(good)
    with np.load(tmp_path / "g.face") as data:
        return {k: data[k] for k in data.files}


def _corrupt_faces(good: bytes, tmp_path) -> dict[str, bytes]:
    arrays = _arrays(good, tmp_path)
    nan_params = dict(arrays, params=arrays["params"].copy())
    nan_params["params"][3] = np.nan
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x10
    return {
        "empty": b"",
        "truncated": good[: len(good) // 2],
        "flipped": bytes(flipped),
        "text": b"name: not a description\n",
        "pts": b"version: 1\nn_points: 68\n{\n1 2\n}\n",
        "jpeg": cv2.imencode(".jpg", np.zeros((8, 8, 3), np.uint8))[1].tobytes(),
        "nan": write_npz(**nan_params),
    }


def _one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("uma: error: ")
    assert "Traceback" not in err and "pickle" not in err and "Warning" not in err
    return lines[0]


KINDS = ["empty", "truncated", "flipped", "text", "pts", "jpeg", "nan"]


@pytest.mark.parametrize("kind", KINDS)
def test_corrupt_description_through_bench_mbc(good_face, astronaut_clip, tmp_path, capsys, kind):
    face = tmp_path / f"{kind}.face"
    face.write_bytes(_corrupt_faces(good_face, tmp_path)[kind])
    code = main(["bench", "mbc", "--video", str(astronaut_clip), "--face", str(face), "--json"])
    line = _one_line(capsys.readouterr().err)
    assert code == 2 and str(face) in line and "expected" in line


def _run_with_description(folder, description: str, capsys) -> str:
    """`uma run` of a WLAN-to-GSM switching scenario whose description is `description`;
    it must be refused (exit 2): its one line."""
    scenario = folder / "s.yaml"
    scenario.write_text(
        "name: probe\nsource: {kind: talking-head, width: 176, height: 144, fps: 25}\n"
        "route:\n  - {technology: WLAN, duration_s: 1}\n  - {technology: GSM, duration_s: 1}\n"
        "engine:\n  policy: oracle\n"
        "  switching: {policy: threshold, to_mbc_below_kbps: 30, to_h264_above_kbps: 60}\n"
        f"  mbc: {{description: {description}}}\nmetrics: {{ssim: false}}\n"
    )
    assert main(["run", str(scenario), "--out", str(folder / "out"), "--quiet"]) == 2
    return _one_line(capsys.readouterr().err)


@pytest.mark.parametrize("kind", ["truncated", "flipped", "jpeg", "nan"])
def test_corrupt_description_in_a_scenario(good_face, tmp_path, capsys, kind):
    (tmp_path / "d.face").write_bytes(_corrupt_faces(good_face, tmp_path)[kind])
    line = _run_with_description(tmp_path, "d.face", capsys)
    out = tmp_path / "out"
    assert "d.face" in line and "expected" in line
    assert not (out / "metrics.json").exists()


def test_nan_description_names_the_array(good_face, tmp_path, capsys, astronaut_clip):
    face = tmp_path / "nan.face"
    face.write_bytes(_corrupt_faces(good_face, tmp_path)["nan"])
    assert main(["bench", "mbc", "--video", str(astronaut_clip), "--face", str(face)]) == 2
    line = _one_line(capsys.readouterr().err)
    assert "params: expected finite numbers, got nan at [3]" in line


@pytest.mark.parametrize(
    "value, fps", [("1000000000000", "25"), ("100000000000000000000000000", "25"), ("10", "1e300")]
)
def test_absurd_fap_file_is_refused_by_source_synth(tmp_path, capsys, value, fps):
    fap = tmp_path / "x.fap"
    fap.write_text(f"2.1 x {fps} 2\n{MASK_JAW}\n0 {value}\n{MASK_JAW}\n1 0\n")
    out = tmp_path / "clip.mp4"
    assert main(["source", "synth", "--fap", str(fap), "--out", str(out), "--size", "64x64"]) == 2
    line = _one_line(capsys.readouterr().err)
    assert f"{fap}:{3 if fps == '25' else 1}:" in line
    assert not out.exists()


@pytest.mark.parametrize("fps", ["nan", "1e300", "0"])
def test_absurd_fps_option_is_refused(tmp_path, capsys, fps):
    out = tmp_path / "clip.mp4"
    code = main(["source", "synth", "--fps", fps, "--frames", "2", "--out", str(out)])
    assert code == 2 and "--fps" in _one_line(capsys.readouterr().err)


def _points_text() -> str:
    return ASTRONAUT.read_text(encoding="utf-8")


def test_points_on_no_face_are_refused_as_a_scenario_description(tmp_path, capsys):
    data = yaml.safe_load(_points_text())
    moved = dict(data, points={k: [x, y + 150] for k, (x, y) in data["points"].items()})
    (tmp_path / "neck.yaml").write_text(yaml.safe_dump(moved))
    line = _run_with_description(tmp_path, "neck.yaml", capsys)
    out = tmp_path / "out"
    assert "neck.yaml" in line and "no detected face" in line
    assert not (out / "metrics.json").exists()


def test_truncated_points_yaml_is_one_line_with_its_line(tmp_path, capsys):
    points = tmp_path / "p.yaml"
    text = _points_text()
    points.write_text(text[: text.index('"4.2"') + 12])  # inside a flow sequence
    assert main(["describe", "--points", str(points), "--out", str(tmp_path)]) == 2
    line = _one_line(capsys.readouterr().err)
    assert f"{points}:" in line and "expected" in line and "got the end of the file" in line


def test_truncated_and_tab_indented_points_json(tmp_path, capsys):
    data = yaml.safe_load(_points_text())
    whole = json.dumps(data, indent="\t")
    points = tmp_path / "p.json"
    points.write_text(whole[:300])
    assert main(["describe", "--points", str(points), "--out", str(tmp_path)]) == 2
    line = _one_line(capsys.readouterr().err)
    assert f"{points}:" in line and "invalid JSON" in line
    points.write_text(whole)  # JSON writers indent with tabs, which YAML does not allow
    assert main(["describe", "--points", str(points), "--out", str(tmp_path)]) == 0
    assert (tmp_path / "astronaut.face").is_file()


def test_unknown_point_id_is_refused_with_line_and_known_ids(tmp_path, capsys):
    points = tmp_path / "p.yaml"
    text = _points_text().replace('  "3.6": ', '  "99.9": [1, 2]\n  "3.6": ')
    points.write_text(text)
    line_no = text.splitlines().index('  "99.9": [1, 2]') + 1
    assert main(["describe", "--points", str(points), "--out", str(tmp_path)]) == 2
    line = _one_line(capsys.readouterr().err)
    assert f"{points}:{line_no} (points['99.9'])" in line
    assert "3.1-3.14" in line and "9.1-9.15" in line


def test_bad_model_yaml_is_one_line(tmp_path, capsys):
    model = tmp_path / "m.yaml"
    whole = (codecs_dir() / "face" / "uma-face.yaml").read_text(encoding="utf-8")
    model.write_text(whole[:3000])
    args = ["describe", "--points", str(ASTRONAUT), "--model", str(model), "--out", str(tmp_path)]
    assert main(args) == 2
    line = _one_line(capsys.readouterr().err)
    assert f"{model}:" in line and "expected" in line and "got" in line


@pytest.mark.parametrize("command", ["run", "describe"])
def test_a_character_yaml_refuses_is_one_line_with_its_line(tmp_path, capsys, command):
    bad = tmp_path / "bad.yaml"
    bad.write_bytes(b"name: x\nroute: \x00\n")
    if command == "run":
        args = ["run", str(bad), "--out", str(tmp_path / "out"), "--quiet"]
    else:
        args = ["describe", "--points", str(bad), "--out", str(tmp_path)]
    assert main(args) == 2
    line = _one_line(capsys.readouterr().err)
    assert f"{bad}:2: " in line and "#x0000" in line


def test_points_on_no_face_are_refused_and_points_off_the_face_warned(tmp_path, capsys):
    data = yaml.safe_load(_points_text())
    for name, dy_px in (("neck", 110), ("low", 40)):
        moved = dict(data, points={k: [x, y + dy_px] for k, (x, y) in data["points"].items()})
        (tmp_path / f"{name}.yaml").write_text(yaml.safe_dump(moved))
    neck = tmp_path / "neck.yaml"
    assert main(["describe", "--points", str(neck), "--out", str(tmp_path)]) == 2
    line = _one_line(capsys.readouterr().err)
    assert str(neck) in line and "no detected face" in line and "another picture" in line
    low = tmp_path / "low.yaml"
    assert main(["describe", "--points", str(low), "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"uma: warning: {low}: ")
    assert "lie away from the face detected" in err[0]


@pytest.mark.parametrize("kind", ["jpeg", "png"])
def test_damaged_image_is_called_so_in_one_line(tmp_path, capfd, kind):
    photo = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    data = bytearray(cv2.imencode(f".{kind}", photo)[1].tobytes())
    if kind == "jpeg":
        data = data[:600]  # truncated: PyAV would open it as a one-frame "video"
    else:
        data[12] ^= 4  # the first chunk's name damaged: OpenCV logs its own line
    image = tmp_path / f"astro.{kind}"
    image.write_bytes(bytes(data))
    assert main(["describe", str(image), "--points", str(ASTRONAUT), "--out", str(tmp_path)]) == 2
    line = _one_line(capfd.readouterr().err)  # file-descriptor level: OpenCV's log counts
    assert str(image) in line and "truncated or damaged" in line and "which frame" not in line


@pytest.mark.parametrize("where", ["file", "unwritable"])
def test_describe_out_that_cannot_be_written_names_the_path(tmp_path, capsys, monkeypatch, where):
    import os

    out = tmp_path / "out"
    if where == "file":
        out.write_text("")
    else:
        out.mkdir()
        # Root writes through any mode bits: say no as a read-only folder would.
        real_access = os.access
        monkeypatch.setattr(
            os, "access", lambda p, m: False if str(p) == str(out) else real_access(p, m)
        )
    assert main(["describe", "--points", str(ASTRONAUT), "--out", str(out)]) == 2
    line = _one_line(capsys.readouterr().err)
    assert str(out) in line and "None" not in line
    assert ("existing file" if where == "file" else "permission denied") in line
    assert not list(tmp_path.glob("**/*.face"))


def test_frame_without_video_takes_the_video_of_the_command_line(astronaut_clip, tmp_path, capsys):
    data = yaml.safe_load(_points_text())
    del data["image"]
    data["frame"] = 1
    points = tmp_path / "p.yaml"
    points.write_text(yaml.safe_dump(data))
    args = ["describe", str(astronaut_clip), "--points", str(points), "--out", str(tmp_path)]
    assert main(args) == 0, capsys.readouterr().err
    assert (tmp_path / "astro.face").is_file()
    # Without the video on the command line, the file names no clip: one line.
    assert main(["describe", "--points", str(points), "--out", str(tmp_path)]) == 2
    assert "no video: names the clip" in _one_line(capsys.readouterr().err)


@pytest.mark.parametrize("where", ["folder", "under-a-file"])
def test_source_synth_out_that_cannot_be_written_names_the_path(tmp_path, capsys, where):
    blocker = tmp_path / "blocker"
    if where == "folder":
        blocker.mkdir()
        out = blocker
    else:
        blocker.write_text("")
        out = blocker / "clip.mp4"
    args = ["source", "synth", "--frames", "2", "--size", "64x64", "--out", str(out)]
    assert main(args) == 2
    line = _one_line(capsys.readouterr().err)
    assert str(blocker) in line and "None" not in line
