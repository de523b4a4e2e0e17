"""`uma bench mbc`: the keys docs/benchmarks.md requires, and bad input as one line with exit 2."""

from __future__ import annotations

import json

import numpy as np
import pytest

from uma.cli import main

DISPLAYS = (
    "unquantised",
    "quantised",
    "frozen",
    "h264_lowest",
    "h264_second",
    "mbc_refresh_lowest",
    "mbc_refresh_second",
)
KEYS = (
    "frames",
    "size",
    "rate_kbps",
    "wire_kbps",
    "psnr_loss_db",
    "reinits",
    "track_ms_median",
    "init_ms_median",
    "render_ms_median",
    "mde_median_px",
    "mde_p95_px",
)


def test_bench_mbc_json_keys(capsys, tmp_path) -> None:
    import cv2

    picture = tmp_path / "side.png"
    assert main(["bench", "mbc", "--frames", "4", "--json", "--picture", str(picture)]) == 0
    result = json.loads(capsys.readouterr().out)
    drawn = cv2.imread(str(picture))
    assert result["picture"] == str(picture) and drawn.shape[0] >= 288 * len(result["clips"])
    assert "talking-head" in result["clips"]
    for name, clip in result["clips"].items():
        for key in KEYS:
            assert key in clip, (name, key)
        assert clip["frames"] == 4
        for region in ("face", "frame", "model"):
            for display in DISPLAYS:
                keys = set(clip[region][display]) - {"kbps"}
                assert keys == {"psnr_db", "ssim", "chroma_psnr_db"}, (name, region, display)
            assert clip[region]["h264_second"]["kbps"] > clip[region]["h264_lowest"]["kbps"] > 0
            refreshed = clip[region]["mbc_refresh_lowest"]["kbps"]
            assert refreshed > clip["rate_kbps"], (name, region)
        for display in ("mbc_refresh_lowest", "mbc_refresh_second"):
            info = clip["refresh"][display]
            assert info["units"] >= 1 and info["refresh_kbps"] > 0, (name, display)
        assert clip["rate_kbps"] > 0 and clip["wire_kbps"] > clip["rate_kbps"]
    head = result["clips"]["talking-head"]
    assert head["size"] == "352x288" and head["mde_median_px"] < 1.0
    for name in set(result["clips"]) - {"talking-head"}:
        assert result["clips"][name]["mde_median_px"] is None


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("uma: error: "), err
    return err[0]


def test_picture_in_a_missing_folder_is_refused(tmp_path, capsys) -> None:
    assert main(["bench", "mbc", "--picture", str(tmp_path / "no" / "p.png")]) == 2
    assert "--picture" in _one_error_line(capsys)


def test_video_without_a_description_is_refused(capsys) -> None:
    assert main(["bench", "mbc", "--video", __file__]) == 2
    assert "--face" in _one_error_line(capsys)


def test_garbage_files_are_one_line_and_exit_2(tmp_path, capsys) -> None:
    face = tmp_path / "x.face"
    face.write_bytes(b"\x00garbage" * 10)
    assert main(["bench", "mbc", "--video", __file__, "--face", str(face)]) == 2
    assert "x.face" in _one_error_line(capsys)


@pytest.fixture(scope="module")
def head_description(tmp_path_factory):
    from uma.face.talking_head import astronaut_description

    return astronaut_description(176, 144)


def test_a_description_not_matching_its_model_is_refused(tmp_path, capsys, head_description):
    from dataclasses import replace

    bad = replace(head_description, params=head_description.params[:8])
    path = tmp_path / "bad.face"
    bad.save(path)
    assert main(["bench", "mbc", "--video", __file__, "--face", str(path)]) == 2
    assert "parameters" in _one_error_line(capsys)


def _write_clip(path, frames) -> None:
    import av

    with av.open(str(path), "w", format="mp4") as container:
        stream = container.add_stream("libx264", rate=25)
        stream.width, stream.height, stream.pix_fmt = 176, 144, "yuv420p"
        for picture in frames:
            frame = av.VideoFrame.from_ndarray(picture, format="gray").reformat(format="yuv420p")
            container.mux(stream.encode(frame))
        container.mux(stream.encode(None))


def test_a_clip_without_a_face_is_one_line_and_exit_2(tmp_path, capsys, head_description):
    rng = np.random.default_rng(0)
    video = tmp_path / "noise.mp4"
    _write_clip(video, [rng.integers(0, 255, (144, 176), dtype=np.uint8) for _ in range(3)])
    face = tmp_path / "head.face"
    head_description.save(face)
    assert main(["bench", "mbc", "--video", str(video), "--face", str(face), "--frames", "3"]) == 2
    assert "no face tracked" in _one_error_line(capsys)


def test_a_clip_of_one_frame_is_one_line_and_exit_2(tmp_path, capsys, head_description):
    video = tmp_path / "one.mp4"
    _write_clip(video, [np.full((144, 176), 100, np.uint8)])
    face = tmp_path / "head.face"
    head_description.save(face)
    assert main(["bench", "mbc", "--video", str(video), "--face", str(face)]) == 2
    assert "one.mp4: holds 1 frame(s): expected at least 2" in _one_error_line(capsys)


def test_an_opening_the_tracker_finds_no_face_in_is_drawn_from_the_description(head_description):
    # frame 0 is a picture (not blank) with no face: the bench runs on from the description's
    # own picture and says so, where it said "picture" before
    import cv2

    from uma.bench.mbc import run_clip
    from uma.bench.mbc_clips import ClipSpec

    face = cv2.cvtColor(head_description.texture, cv2.COLOR_BGR2YUV_I420)
    noise = np.random.default_rng(0).integers(0, 256, face.shape, dtype=np.uint8)
    # the tracker tries again 10 frames after a failed initialisation
    clip = ClipSpec("late", [noise] + [face] * 11, 25.0, head_description, None, "late.mp4")
    result = run_clip(clip, refresh={})
    assert result["reference"] == "description" and result["frames"] == 12
    assert 1 <= result["failures"] <= 10
