"""AV1 through SVT-AV1 and dav1d: one packet per frame, key frames on request, rate, round trip."""

import numpy as np
import pytest
from codec_checks import pattern, round_trip_psnr_db, steady_kbps

from uma.errors import ConfigError, VideoError
from uma.metrics.quality import psnr_db
from uma.video import (
    AV1Decoder,
    AV1Encoder,
    VideoFileSource,
    default_ladder_path,
    load_ladder,
    resize_yuv420,
)

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


@pytest.fixture(scope="module")
def carphone(shared_data):
    return list(VideoFileSource(shared_data / "faces" / "video" / "carphone_qcif.mp4").frames())


def test_one_packet_per_frame_and_key_frames_only_where_asked():
    encoder = AV1Encoder(176, 144, 25, 200)
    out = [encoder.encode(f, force_idr=i == 6) for i, f in enumerate(pattern(10))]
    assert [o.pts for o in out] == list(range(10))
    assert [i for i, o in enumerate(out) if o.is_keyframe] == [0, 6]
    # every key frame carries the sequence header, so a decoder can start there
    headed = [i for i, o in enumerate(out) if OBU_SEQUENCE_HEADER in obu_types(o.data)]
    assert headed == [0, 6] and obu_types(out[1].data)[0] == 2


def test_round_trip_shape_and_quality():
    # measured 40.7 dB at 300 kbit/s
    assert round_trip_psnr_db(AV1Encoder(176, 144, 25, 300), AV1Decoder(), pattern(15)) > 36


def test_forced_key_frame_decodes_alone():
    frames = pattern(8)
    encoder = AV1Encoder(176, 144, 25, 300)
    out = [encoder.encode(f, force_idr=i == 6) for i, f in enumerate(frames)]
    picture = AV1Decoder().decode(out[6].data)  # measured 41.5 dB
    assert picture.shape == (216, 176) and psnr_db(frames[6][:144], picture[:144]) > 35


def test_rate_near_target_on_carphone(carphone):
    # measured -0.3 % (128 kbit/s, QCIF, 25 frames/s, 6 s); the ladder's rungs in docs/codecs.md
    encoder = AV1Encoder(176, 144, 25, 128)
    got = steady_kbps([encoder.encode(f).size_bits for f in carphone[:150]], 25)
    assert 0.93 * 128 <= got <= 1.05 * 128, got


def test_quality_rises_with_rate():
    # measured 36.7 dB at 60 kbit/s, 41.6 dB at 600
    low, high = (
        round_trip_psnr_db(AV1Encoder(176, 144, 25, rate), AV1Decoder(), pattern(15))
        for rate in (60, 600)
    )
    assert high > low + 3


def test_encoding_is_deterministic():
    frames = pattern(8)
    runs = [AV1Encoder(176, 144, 25, 100) for _ in range(2)]
    a, b = ([encoder.encode(f).data for f in frames] for encoder in runs)
    assert a == b


def test_real_time_low_delay_cbr_settings_recorded():
    encoder = AV1Encoder(352, 288, 25, 300)
    assert encoder.options["preset"] == "12"
    params = dict(item.split("=") for item in encoder.svtav1_params.split(":"))
    assert params["rtc"] == "1" and params["pred-struct"] == "1" and params["rc"] == "2"
    assert params["buf-sz"] == "160" and params["lp"] == "1"  # 4 frame intervals at 25 fps
    assert AV1Encoder(176, 144, 25, 100, preset=10).options["preset"] == "10"


def test_rung_change_to_a_new_size_decodes_on_the_same_decoder():
    decoder = AV1Decoder()
    frames = pattern(3, 352, 288)
    assert decoder.decode(AV1Encoder(352, 288, 25, 500).encode(frames[0]).data).shape == (432, 352)
    small = AV1Encoder(176, 144, 12.5, 100).encode(resize_yuv420(frames[1], 176, 144))
    assert small.is_keyframe and decoder.decode(small.data).shape == (216, 176)


def test_garbage_and_empty_packets_raise_video_error_and_the_decoder_recovers():
    out = [AV1Encoder(176, 144, 25, 200).encode(f) for f in pattern(2)]
    decoder = AV1Decoder()
    junk = bytes(np.random.default_rng(0).integers(0, 256, 500, dtype=np.uint8))
    try:
        assert decoder.decode(junk) is None
    except VideoError as err:
        assert "corrupt bitstream" in str(err)
    with pytest.raises(VideoError, match="empty packet"):
        decoder.decode(b"")
    assert decoder.decode(out[0].data).shape == (216, 176)
    assert decoder.decode(out[1].data).shape == (216, 176)


def test_encoder_rejects_bad_frames_and_settings():
    encoder = AV1Encoder(176, 144, 25, 100)
    with pytest.raises(VideoError, match="expected a"):
        encoder.encode(np.zeros((144, 176), dtype=np.uint8))
    with pytest.raises(VideoError, match="even"):
        AV1Encoder(175, 144, 25, 100)
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
