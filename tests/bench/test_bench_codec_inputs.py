"""Issue 28, items 4 and 8: `uma bench codec --video` bounds its work by the clip (the frames
it holds, streamed, never a list of --frames), says what a large clip will cost, and refuses a
clip it cannot score in one line, exit 2."""

import json
import os
import re

import numpy as np
import pytest

from uma.bench.codec import measure_rung
from uma.bench.codec_clip import MAX_PIXELS, open_clip
from uma.cli import main
from uma.errors import VideoError
from uma.video import Rung, default_ladder_path, load_ladder


def make_clip(path, width, height, frames):
    import av

    rng = np.random.default_rng(0)
    with av.open(str(path), "w") as container:
        stream = container.add_stream("ffv1", rate=25)
        stream.width, stream.height, stream.pix_fmt = width, height, "yuv420p"
        for _ in range(frames):
            picture = rng.integers(0, 255, (height * 3 // 2, width), dtype=np.uint8)
            for packet in stream.encode(av.VideoFrame.from_ndarray(picture, format="yuv420p")):
                container.mux(packet)
        for packet in stream.encode():
            container.mux(packet)
    return path


@pytest.fixture(scope="module")
def clip40(tmp_path_factory):
    return make_clip(tmp_path_factory.mktemp("clips") / "clip40.mkv", 96, 64, 40)


def test_a_billion_frames_asked_codes_the_forty_the_clip_holds(clip40, capsys):
    clip = open_clip(clip40, 10**9)
    assert clip.count == 40 and len(clip.boxes) == 40 and (clip.width, clip.height) == (96, 64)
    argv = ["bench", "codec", "--codec", "vp8", "--video", str(clip40), "--frames", "1000000000"]
    assert main([*argv, "--json"]) == 0
    out, err = capsys.readouterr()
    data = json.loads(out)["codecs"]["vp8"]["clips"]["clip40"]
    assert data["frames"] == 40 and data["size"] == "96x64"
    assert err == ""  # 40 small frames: nothing to warn about


def test_a_rung_is_measured_from_frames_streamed_once(clip40):
    clip = open_clip(clip40, 40, faces=False)
    frames = clip.frames()  # a generator: measure_rung must not index or re-read it
    settings = load_ladder(default_ladder_path("vp8")).encoder
    row = measure_rung("vp8", Rung(64, 96, 64, 25), settings, frames, [None] * 40)
    assert row["psnr_db"] > 0 and next(frames, None) is None


@pytest.mark.parametrize(
    "size, frames, said",
    [
        ((2, 2), 40, "a 2x2 picture is below the minimum 16x16 the benchmark scores"),
        ((12, 12), 40, "a 12x12 picture is below the minimum 16x16"),
        ((96, 64), 10, "10 frames, expected at least 30"),
        ((3856, 2176), 1, "a 3856x2176 picture (8.4 Mpixels) is above the maximum 3840x2160"),
    ],
)
def test_a_clip_it_cannot_score_is_one_line(tmp_path, capsys, size, frames, said):
    assert (size[0] * size[1] > MAX_PIXELS) == (size[0] > 3840)
    path = make_clip(tmp_path / "c.mkv", *size, frames)
    with pytest.raises(VideoError, match=re.escape(said)):
        open_clip(path, 300)
    code = main(["bench", "codec", "--codec", "vp8", "--video", str(path), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and said in err, err


def test_a_fifo_or_a_loop_as_the_video_is_refused(tmp_path, capsys):
    os.mkfifo(tmp_path / "fifo.mp4")
    (tmp_path / "loop.mp4").symlink_to(tmp_path / "loop.mp4")
    for name, said in (("fifo.mp4", "got a FIFO"), ("loop.mp4", "a symlink loop")):
        code = main(["bench", "codec", "--video", str(tmp_path / name), "--quiet"])
        err = capsys.readouterr().err
        assert code == 2 and err.startswith("uma: error: --video: ") and said in err, err
