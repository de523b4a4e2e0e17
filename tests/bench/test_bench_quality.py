"""`uma bench quality`: its keys, and that it measures agreement rather than assuming it."""

import json

from uma.cli import main


def test_bench_quality_json_keys_on_one_clip(capsys, shared_data):
    clip = shared_data / "faces" / "video" / "carphone_qcif.mp4"
    argv = ["bench", "quality", "--video", str(clip), "--pairs", "9", "--repeats", "3", "--json"]
    assert main(argv) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["pairs"] == 9 and set(result["clips"]) == {"carphone_qcif"}
    assert 0 <= result["ssim_max_abs_diff"] < 1e-6
    assert result["pairs_with_face"] == 0 or result["ssim_face_max_abs_diff"] < 1e-6
    assert result["psnr_max_abs_diff_db"] == 0.0
    # float32 scikit-image is itself a little off its float64 result: a real difference shows
    assert result["ssim_max_abs_diff_vs_float32"] > 0
    timing = result["timing"]
    assert timing["plane"] == "176x144"
    for row in (timing["default_malloc"], timing["keep_freed_memory"]):
        if row is not None:
            assert row["ssim_ms"] > 0 and row["skimage_float32_ms"] > 0
            assert row["speedup_vs_float32"] > 0


def test_bench_quality_refuses_bad_options(capsys):
    assert main(["bench", "quality", "--pairs", "0"]) == 2
    assert "--pairs" in capsys.readouterr().err
    assert main(["bench", "quality", "--video", "/no/such/clip.mp4"]) == 2
    assert "--video" in capsys.readouterr().err
