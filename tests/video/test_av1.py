"""AV1 through SVT-AV1 and dav1d: one packet per frame, key frames on request, rate, round trip."""

import codec_checks as checks
import pytest

from uma.errors import ConfigError, VideoError
from uma.video import AV1Encoder, default_ladder_path, load_ladder

OBU_SEQUENCE_HEADER = 1  # obu_type (AV1 spec 5.3.1); a temporal unit starts with a delimiter (2)


def obu_types(data):
    """The obu_type of each OBU in a temporal unit whose OBUs all carry their size."""
    types, at = [], 0
    while at < len(data):
        header = data[at]
        types.append(header >> 3 & 0xF)
        at += 2 if header & 0x4 else 1  # extension byte
        size, shift = 0, 0
        while True:  # leb128
            byte = data[at]
            at += 1
            size |= (byte & 0x7F) << shift
            shift += 7
            if not byte & 0x80:
                break
        at += size
    return types


def test_one_packet_per_frame_and_key_frames_only_where_asked():
    _, out = checks.forced_key_frames(AV1Encoder(176, 144, 25, 200), 10, 6)
    # every key frame carries the sequence header, so a decoder can start there
    headed = [i for i, o in enumerate(out) if OBU_SEQUENCE_HEADER in obu_types(o.data)]
    assert headed == [0, 6] and obu_types(out[1].data)[0] == 2


def test_real_time_low_delay_cbr_settings_recorded():
    encoder = AV1Encoder(352, 288, 25, 300)
    assert encoder.options["preset"] == "12"
    params = dict(item.split("=") for item in encoder.svtav1_params.split(":"))
    assert params["rtc"] == "1" and params["pred-struct"] == "1" and params["rc"] == "2"
    assert params["buf-sz"] == "160" and params["lp"] == "1"  # 4 frame intervals at 25 fps
    assert AV1Encoder(176, 144, 25, 100, preset=10).options["preset"] == "10"


def test_encoder_rejects_bad_settings():
    with pytest.raises(VideoError, match="preset"):
        AV1Encoder(176, 144, 25, 100, preset=13)
    with pytest.raises(VideoError, match="keyint_frames"):
        AV1Encoder(176, 144, 25, 100, keyint_frames=0)


def test_ladder_file_has_the_h264_rungs_and_av1_settings(tmp_path):
    ladder = load_ladder(default_ladder_path("av1"))
    assert ladder.codec == "av1" and ladder.rungs == load_ladder().rungs
    assert ladder.encoder.kwargs() == {"preset": 12, "keyint_frames": 250, "vbv_frames": 4}
    rung = ladder.rungs[0]
    AV1Encoder(rung.width, rung.height, rung.fps, rung.rate_kbps, **ladder.encoder.kwargs())
    path = tmp_path / "a.yaml"
    path.write_text(
        "codec: av1\nencoder:\n  preset: fast\nrungs:\n"
        "  - {rate_kbps: 20, width: 128, height: 96, fps: 5}\n"
    )
    with pytest.raises(ConfigError, match=r"a\.yaml:3 \(encoder\.preset\): expected an SVT-AV1"):
        load_ladder(path)
