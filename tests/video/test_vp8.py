"""VP8 through libvpx: one frame out per frame in, key frames on request, rate and round trip."""

import codec_checks as checks
import pytest

from uma.errors import ConfigError, VideoError
from uma.video import VP8Encoder, default_ladder_path, load_ladder


def test_one_frame_out_per_frame_in_and_key_frames_only_where_asked():
    _, out = checks.forced_key_frames(VP8Encoder(176, 144, 25, 200), 20, 12)
    # VP8's frame tag: bit 0 of the first byte is 0 on a key frame
    assert [i for i, o in enumerate(out) if not o.data[0] & 1] == [0, 12]


def test_webrtc_speed_by_size_and_settings_recorded():
    assert VP8Encoder(176, 144, 25, 100).cpu_used == -4
    big = VP8Encoder(352, 288, 25, 300)
    assert big.cpu_used == -6 and big.options["deadline"] == "realtime"
    assert big.options["minrate"] == big.options["maxrate"] == "300000"  # CBR
    assert big.options["bufsize"] == str(4 * 300_000 // 25)
    assert VP8Encoder(176, 144, 25, 100, cpu_used=-8).options["cpu-used"] == "-8"


def test_encoder_rejects_bad_settings():
    with pytest.raises(VideoError, match="cpu_used"):
        VP8Encoder(176, 144, 25, 100, cpu_used=40)
    with pytest.raises(VideoError, match="vbv_frames"):
        VP8Encoder(176, 144, 25, 100, vbv_frames=0.5)


def test_ladder_file_has_the_h264_rungs_and_vp8_settings():
    ladder, h264 = load_ladder(default_ladder_path("vp8")), load_ladder()
    assert ladder.codec == "vp8" and ladder.source.endswith("vp8.yaml")
    assert ladder.rungs == h264.rungs
    assert ladder.encoder.kwargs() == {"cpu_used": None, "keyint_frames": 250, "vbv_frames": 4}
    rung = ladder.rungs[0]
    VP8Encoder(rung.width, rung.height, rung.fps, rung.rate_kbps, **ladder.encoder.kwargs())


def test_ladder_file_errors_name_line_and_key(tmp_path):
    path = tmp_path / "v.yaml"
    rung = "rungs:\n  - {rate_kbps: 20, width: 128, height: 96, fps: 5}\n"
    path.write_text("codec: vp8\nencoder: {cpu_used: 99}\n" + rung)
    with pytest.raises(ConfigError, match=r"v\.yaml:2 \(encoder\.cpu_used\): expected an integer"):
        load_ladder(path)
    path.write_text("codec: vp8\nencoder: {preset: fast}\n" + rung)
    with pytest.raises(ConfigError, match=r"unknown key 'preset'; expected keys cpu_used"):
        load_ladder(path)
    path.write_text("codec: vp9\n" + rung)
    with pytest.raises(ConfigError, match=r"v\.yaml:1 \(codec\): expected one of h264, vp8, av1"):
        load_ladder(path)
