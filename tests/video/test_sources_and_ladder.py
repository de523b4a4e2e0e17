import numpy as np
import pytest

from uma.errors import ConfigError, VideoError
from uma.video import PatternSource, RawYuvSource, VideoFileSource, load_ladder


def test_video_file_source_reads_real_clip(shared_data):
    source = VideoFileSource(shared_data / "faces" / "video" / "carphone_qcif.mp4", max_frames=10)
    frames = list(source.frames())
    assert (source.width, source.height) == (176, 144)
    assert len(frames) == 10 and frames[0].shape == (216, 176) and frames[0].dtype == np.uint8


def test_loop_repeats_a_short_clip(shared_data):
    path = shared_data / "faces" / "video" / "foreman_part_qcif.yuv"
    source = RawYuvSource(path, 176, 144, 25, loop=True)
    assert source.frame_count == 48
    it = source.frames()
    frames = [next(it) for _ in range(50)]
    assert np.array_equal(frames[0], frames[48])


def test_missing_and_undecodable_files(tmp_path):
    with pytest.raises(VideoError, match="no such video file"):
        VideoFileSource(tmp_path / "none.mp4")
    fake = tmp_path / "notes.mp4"
    fake.write_text("this is not a video\n" * 50)
    with pytest.raises(VideoError, match="notes.mp4"):
        VideoFileSource(fake)


def test_yuv_size_must_match(tmp_path):
    path = tmp_path / "x.yuv"
    path.write_bytes(bytes(176 * 144 * 3 // 2 + 5))
    with pytest.raises(VideoError, match="not a whole number of 176x144"):
        RawYuvSource(path, 176, 144, 25)


def test_pattern_source_moves_and_is_deterministic():
    a = PatternSource(176, 144, seed=1).frames()
    b = PatternSource(176, 144, seed=1).frames()
    fa = [next(a) for _ in range(30)]
    fb = [next(b) for _ in range(30)]
    assert all(np.array_equal(x, y) for x, y in zip(fa, fb, strict=True))
    assert not np.array_equal(fa[0], fa[29])


def test_default_ladder_is_ascending_and_valid():
    ladder = load_ladder()
    rates = [r.rate_kbps for r in ladder.rungs]
    assert rates == sorted(rates) and len(rates) >= 5
    assert all(r.width % 2 == 0 and r.height % 2 == 0 for r in ladder.rungs)


@pytest.mark.parametrize(
    "body, message",
    [
        (
            "rungs:\n  - {rate_kbps: 10, width: 176, height: 144, fps: -1}\n",
            r"h\.yaml:2 \(rungs\[0\]\.fps\): expected a positive number",
        ),
        (
            "rungs:\n  - {rate_kbps: 10, width: 175, height: 144, fps: 5}\n",
            r"rungs\[0\]\.width\): expected an even",
        ),
        (
            "rungs:\n  - {rate_kbps: 20, width: 176, height: 144, fps: 5}\n  - {rate_kbps: 10, width: 176, height: 144, fps: 5}\n",
            r"rungs\[1\]\.rate_kbps: expected more",
        ),
        ("rungs:\n  - {rate: 20, width: 176, height: 144, fps: 5}\n", r"expected keys rate_kbps"),
        ("ladder: []\n", r"expected a mapping with one key 'rungs'"),
    ],
)
def test_ladder_errors_name_file_and_key(tmp_path, body, message):
    path = tmp_path / "h.yaml"
    path.write_text(body)
    with pytest.raises(ConfigError, match=message):
        load_ladder(path)
