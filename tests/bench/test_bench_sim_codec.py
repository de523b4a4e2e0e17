"""`uma bench sim --codec`: the simulation timed on another full-frame codec's ladder."""

import json

import pytest

import uma.video
from uma.cli import main
from uma.codecs import REGISTRY, full_frame_names


def test_an_unknown_codec_is_one_line_and_exit_2(capsys):
    assert main(["bench", "sim", "--frames", "5", "--size", "qcif", "--codec", "mpeg2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--codec: expected one of h264" in err[0] and "'mpeg2'" in err[0]


@pytest.mark.parametrize("codec", full_frame_names())
def test_the_run_and_its_replay_use_the_codec(codec, capsys):
    if not hasattr(uma.video, REGISTRY[codec].video_encoder):
        pytest.skip(f"uma.video has no {REGISTRY[codec].video_encoder} in this checkout")
    argv = ["bench", "sim", "--frames", "20", "--size", "qcif", "--codec", codec, "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["codec"] == codec
    assert codec in out["codecs"] and out["codec_s_by_codec"][codec] > 0
