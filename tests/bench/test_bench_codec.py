"""`uma bench codec --codec ...`: the per-codec, per-rung keys, the plot, the ffmpeg check."""

import json
import shutil

import pytest

from uma.bench.codec import (
    CODEC_NAMES,
    RUNG_KEYS,
    measure_rung,
    plot_rate_quality,
    run_codecs_bench,
)
from uma.cli import main
from uma.face.detect import Box
from uma.video import PatternSource, Rung, default_ladder_path, load_ladder


@pytest.fixture(scope="module")
def carphone_path(shared_data):
    return shared_data / "faces" / "video" / "carphone_qcif.mp4"


def test_every_rung_of_the_codec_on_the_pattern():
    result = run_codecs_bench(("vp8",), [None], frames=30, pattern_size=(176, 144))
    assert list(result["codecs"]["vp8"]) == ["ladder", "clips"]
    clip = result["codecs"]["vp8"]["clips"]["pattern"]
    assert clip["frames"] == 30 and clip["size"] == "176x144"
    rungs = clip["rungs"]
    assert [r["target_kbps"] for r in rungs] == [r.rate_kbps for r in load_ladder().rungs]
    assert all(set(RUNG_KEYS) <= set(r) and r["psnr_face_db"] is None for r in rungs)
    assert rungs[-1]["psnr_db"] > rungs[0]["psnr_db"] + 3


@pytest.mark.slow  # about 3 s idle, most of it importing scikit-image and detecting faces
def test_json_has_every_rung_of_the_codec_on_the_clip(capsys, carphone_path):
    args = ["bench", "codec", "--codec", "vp8", "--frames", "30", "--video", str(carphone_path)]
    assert main([*args, "--json", "--quiet"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert list(result) == ["codecs"]  # no H.264 section without H.264
    clip = result["codecs"]["vp8"]["clips"]["carphone"]
    assert clip["frames"] == 30 and clip["size"] == "176x144"
    rungs = clip["rungs"]
    assert [r["target_kbps"] for r in rungs] == [r.rate_kbps for r in load_ladder().rungs]
    for rung in rungs:
        assert set(RUNG_KEYS) <= set(rung)
        assert 15 < rung["psnr_db"] < 60 and 0.5 < rung["ssim"] <= 1
        assert rung["psnr_face_db"] is not None and rung["encode_ms"] > 0
    # quality rises from the lowest rung to the highest
    assert rungs[-1]["psnr_db"] > rungs[0]["psnr_db"] + 3


def test_measure_rung_hits_the_rate_and_scores_the_face_box_where_there_is_one():
    frames = list(PatternSource(176, 144, seed=0, frame_count=50).frames())
    settings = load_ladder(default_ladder_path("vp8")).encoder
    boxes = [None] * 25 + [Box(40, 30, 64, 64)] * 25
    row = measure_rung("vp8", Rung(128, 176, 144, 25), settings, frames, boxes)
    assert 0.9 < row["kbps"] / 128 < 1.1, row  # measured +0.2 %
    assert row["psnr_db"] > 25 and row["decode_ms"] > 0 and row["encode_ms"] > 0
    assert 20 < row["psnr_face_db"] < 60 and 0 < row["ssim_face"] <= 1
    none = measure_rung("vp8", Rung(128, 176, 144, 25), settings, frames, [None] * 50)
    assert none["psnr_face_db"] is None and none["ssim_face"] is None


def test_plot_draws_a_png(tmp_path):
    rung = dict.fromkeys(RUNG_KEYS, 1.0)
    result = {
        "codecs": {
            codec: {
                "clips": {
                    "akiyo": {"rungs": [{**rung, "kbps": k, "psnr_db": k / 10} for k in (16, 64)]}
                }
            }
            for codec in CODEC_NAMES
        }
    }
    path = tmp_path / "rq.png"
    plot_rate_quality(result, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_plot_folder_is_a_usage_error(capsys):
    assert main(["bench", "codec", "--codec", "vp8", "--plot", "/no/such/dir/rq.png"]) == 2
    assert "--plot" in capsys.readouterr().err


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="no ffmpeg command line")
def test_ffmpeg_command_line_repeats_the_vp8_settings():
    from uma.bench.codec_ffmpeg import compare_rung

    frames = list(PatternSource(176, 144, seed=0, frame_count=40).frames())
    settings = load_ladder(default_ladder_path("vp8")).encoder
    row = compare_rung("vp8", Rung(128, 176, 144, 25), settings, frames)
    # measured byte-identical with Debian 12's ffmpeg 5.1 (libvpx 1.12) and PyAV's libvpx 1.16
    assert abs(row["diff_pct"]) < 2, row


def test_ffmpeg_arguments_repeat_each_encoders_own_options():
    """The command line gets the encoder's library, rate and AVOptions, into its raw muxer."""
    from uma.bench.codec import codec_classes
    from uma.bench.codec_ffmpeg import encoder_arguments

    for codec in ("h264", "vp8"):
        settings = load_ladder(default_ladder_path(codec)).encoder
        encoder = codec_classes(codec)[0](176, 144, 25, 128, **settings.kwargs())
        args, muxer = encoder_arguments(encoder)
        assert args[:4] == ["-c:v", encoder.library, "-b:v", str(encoder.bit_rate)]
        for key, value in encoder.options.items():
            assert args[args.index(f"-{key}") + 1] == value
        assert muxer == {"h264": "h264", "vp8": "ivf"}[codec]
