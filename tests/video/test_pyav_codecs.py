"""What VP8 and AV1 share through `uma.video.pyav_codec`: round trips, key frames, rate, recovery.

Each codec's own checks (its key-frame marks, its settings, its ladder file) stay in its module.
"""

import codec_checks as checks
import pytest

from uma.video import AV1Decoder, AV1Encoder, VideoFileSource, VP8Decoder, VP8Encoder

# codec -> (encoder, decoder, floor of a forced key frame's PSNR dB, gain from 60 to 600 kbit/s)
# measured: key frame VP8 39.4 dB, AV1 41.5 dB; 60 -> 600 kbit/s VP8 34.4 -> 44.8, AV1 36.7 -> 41.6
CODECS = {
    "vp8": (VP8Encoder, VP8Decoder, 33, 5),
    "av1": (AV1Encoder, AV1Decoder, 35, 3),
}


@pytest.fixture(params=sorted(CODECS))
def codec(request):
    return CODECS[request.param]


@pytest.fixture(scope="module")
def carphone(shared_data):
    return list(VideoFileSource(shared_data / "faces" / "video" / "carphone_qcif.mp4").frames())


def test_round_trip_shape_and_quality(codec):
    encoder, decoder, _, _ = codec
    # measured 41.2 dB (VP8) and 40.7 dB (AV1) at 300 kbit/s
    psnr = checks.round_trip_psnr_db(encoder(176, 144, 25, 300), decoder(), checks.pattern(15))
    assert psnr > 36


def test_forced_key_frame_decodes_alone(codec):
    encoder, decoder, floor_db, _ = codec
    checks.check_key_frame_decodes_alone(encoder(176, 144, 25, 300), decoder(), floor_db)


def test_rate_near_target_on_carphone(codec, carphone):
    # measured -0.7 % (VP8), -0.3 % (AV1) at 128 kbit/s, QCIF, 25 frames/s, 6 s
    checks.check_rate_near_target(codec[0](176, 144, 25, 128), carphone[:150])


def test_quality_rises_with_rate(codec):
    encoder, decoder, _, gain_db = codec
    checks.check_quality_rises(lambda rate: encoder(176, 144, 25, rate), decoder, gain_db=gain_db)


def test_encoding_is_deterministic(codec):
    checks.check_deterministic(lambda: codec[0](176, 144, 25, 100))


def test_rung_change_to_a_new_size_decodes_on_the_same_decoder(codec):
    checks.check_rung_change(codec[0], codec[1]())


def test_garbage_and_empty_packets_raise_video_error_and_the_decoder_recovers(codec):
    checks.check_garbage_then_recovery(codec[0](176, 144, 25, 200), codec[1]())


def test_encoder_rejects_bad_frames_and_sizes(codec):
    checks.check_bad_frames_and_sizes(codec[0])
