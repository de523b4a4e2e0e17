"""`uma bench face-rung`: its options, and a smoke run on a few real frames."""

from pathlib import Path

import pytest

from uma.bench import face_rung
from uma.cli import main

DATA = Path(__file__).parents[2] / ".." / "shared" / "data" / "faces" / "video"


def test_rung_option_parses_into_validated_rungs():
    config = face_rung.face_config(["6:48x48@5", "10:64x64@8.333333"])
    assert [(r.rate_kbps, r.width, r.height, r.fps) for r in config.rungs] == [
        (6.0, 48, 48, 5.0),
        (10.0, 64, 64, 8.333333),
    ]
    assert config.enabled and face_rung.face_config(None).rungs[0].rate_kbps == 8.0


@pytest.mark.skipif(not (DATA / "carphone_qcif.mp4").exists(), reason="needs ../shared/data")
def test_quote_on_carphone_scores_both_displays(capsys):
    assert main(["bench", "face-rung", "--quote", "carphone", "--frames", "30"]) == 0
    import json

    result = json.loads(capsys.readouterr().out)["quote"]
    assert result["frames"] == 30
    lowest = result["h264_lowest"]
    assert lowest["label"] == "h264 16k 128x96@5" and 15 < lowest["psnr_face_db"] < 40
    for row in result["h264_face"]:
        assert row["failures"] == 0 and row["kbps"] > 0
        assert 15 < row["psnr_face_db"] < 40 and 0 < row["ssim_face"] < 1


@pytest.mark.parametrize(
    "argv",
    [
        ["--quote", "nosuchclip"],
        ["--rung", "8-48x48@5", "--quote", "carphone"],
        ["--frames", "0", "--cost"],
        [],
    ],
)
def test_bad_options_are_one_line_and_exit_2(argv, capsys):
    assert main(["bench", "face-rung", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("uma: error:") and "\n" not in err
