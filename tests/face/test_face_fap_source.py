"""The talking head animated from an MPEG-4 .fap file (`uma source synth --fap`)."""

import json
from pathlib import Path

import av
import numpy as np
import pytest

from uma.cli import main
from uma.face import FapSequence, TalkingHeadSource, fap_units, read_fap
from uma.face.geometry import N_POSE


def test_fap_frames_drive_rotation_and_actions():
    sequence = FapSequence(
        name="nod", fps=12.5, frames=({}, {48: 5000, 3: 400}, {49: -3000, 19: 1024, 20: 1024})
    )
    source = TalkingHeadSource(176, 144, sequence.fps, seed=1, fap=sequence, frame_count=3)
    base = source.description.params
    names = source.model.action_unit_names
    p0, p1, p2 = (source.params_at(i) for i in range(3))
    assert np.allclose(p0, base)  # no FAPs: the template's neutral face
    assert p1[3] == pytest.approx(base[3] + 0.05) and np.allclose(p1[:3], base[:3])
    assert p1[N_POSE + names.index("jaw_drop")] > base[N_POSE + names.index("jaw_drop")]
    assert p2[4] == pytest.approx(base[4] - 0.03)
    units = fap_units(source.model)
    eye = N_POSE + names.index("eye_close")
    # The upper lids close by one IRISD: eye_close moves them 0.09 model units per unit.
    assert p2[eye] - base[eye] == pytest.approx(1024 * units.irisd / 0.09, rel=0.25)
    assert source.params_at(10).tolist() == p2.tolist()  # the last frame holds
    assert source.light_at(2) == (1.0, pytest.approx(np.array([0.0, 0.0, 1.0])))
    frames = list(source.frames())
    assert len(frames) == 3 and frames[0].shape == (144 * 3 // 2, 176)
    assert np.abs(frames[2].astype(int) - frames[0].astype(int)).mean() > 1.0


def test_cli_synth_from_a_shared_fap(shared_data, tmp_path, capsys):
    fap = shared_data / "faces" / "fap" / "joy.fap"
    out = tmp_path / "joy.mp4"
    args = ["source", "synth", "--fap", str(fap), "--frames", "6", "--size", "176x144"]
    assert main([*args, "--out", str(out), "--quiet"]) == 0
    assert "6 frames 176x144@25" in capsys.readouterr().out
    truth = json.loads(out.with_suffix(".truth.json").read_text())
    assert truth["fps"] == 25.0 and len(truth["frames"]) == 6
    assert Path(truth["fap"]).resolve() == fap.resolve()
    sequence = read_fap(fap)
    base = np.array(truth["frames"][0]["params"]) - 1e-5 * np.array(
        [0, 0, 0, *(sequence.frames[0].get(k, 0) for k in (48, 49, 50))] + [0] * 7
    )
    for row, faps in zip(truth["frames"], sequence.frames, strict=False):
        rotation = np.array(row["params"][3:6]) - base[3:6]
        want = [1e-5 * faps.get(k, 0) for k in (48, 49, 50)]
        assert np.allclose(rotation, want, atol=2e-6)
    with av.open(str(out)) as container:
        assert sum(1 for _ in container.decode(video=0)) == 6


@pytest.mark.parametrize(
    "extra, message",
    [(["--frames", "500"], "holds only 108 frames"), (["--fps", "30"], "plays at 25")],
)
def test_cli_synth_fap_bad_options(shared_data, tmp_path, capsys, extra, message):
    fap = shared_data / "faces" / "fap" / "joy.fap"
    out = tmp_path / "x.mp4"
    assert main(["source", "synth", "--fap", str(fap), *extra, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert not out.exists()


def test_cli_synth_malformed_fap(tmp_path, capsys):
    bad = tmp_path / "bad.fap"
    bad.write_text("2.1 bad 25 1\n" + "1 " * 67 + "\n0 5\n")
    assert main(["source", "synth", "--fap", str(bad), "--out", str(tmp_path / "x.mp4")]) == 2
    err = capsys.readouterr().err.strip()
    assert f"{bad}:2:" in err and "68 flags" in err
