import numpy as np
import pytest

from uma.errors import VideoError
from uma.metrics.quality import psnr_db
from uma.video import H264Decoder, H264Encoder, PatternSource, VideoFileSource, resize_yuv420


def clip(shared_data, frames=150):
    path = shared_data / "faces" / "video" / "akiyo.mp4"
    return list(VideoFileSource(path, max_frames=frames).frames())


def measured_kbps(frames, rate_kbps, fps, width, height):
    encoder = H264Encoder(width, height, fps, rate_kbps)
    bits = [encoder.encode(frame).size_bits for frame in frames]
    skip = int(fps)  # the first second carries the IDR
    return sum(bits[skip:]) / ((len(bits) - skip) / fps) / 1000.0


# Measured on akiyo (static talking head, the hard case for undershoot): -3.5 % to -5.3 % at
# 64 kbit/s and above, -10 % to -15 % at 16-24 kbit/s where x264 cannot spend bits on a still
# scene at 5 fps; never over the target. Foreman moves more and lands closer.
@pytest.mark.parametrize(
    "rate_kbps, width, height, fps, low, high",
    [
        (24, 176, 144, 5.0, 0.80, 1.05),
        (64, 176, 144, 12.5, 0.90, 1.05),
        (384, 352, 288, 25.0, 0.90, 1.05),
        (1200, 352, 288, 25.0, 0.90, 1.05),
    ],
)
def test_encoder_hits_target_rate_on_real_video(
    shared_data, rate_kbps, width, height, fps, low, high
):
    frames = clip(shared_data, 300)
    step = int(round(25 / fps))
    frames = [resize_yuv420(f, width, height) for f in frames[::step]]
    got = measured_kbps(frames, rate_kbps, fps, width, height)
    assert low * rate_kbps <= got <= high * rate_kbps, got


def test_encoder_rate_on_foreman_yuv(shared_data):
    from uma.video import RawYuvSource

    source = RawYuvSource(shared_data / "faces" / "video" / "foreman_part_qcif.yuv", 176, 144, 25)
    frames = list(source.frames()) * 3
    got = measured_kbps(frames, 128, 25.0, 176, 144)
    assert 0.85 * 128 <= got <= 1.1 * 128, got


def pattern(n, width=176, height=144):
    source = PatternSource(width, height, seed=2)
    it = source.frames()
    return [next(it) for _ in range(n)]


def test_one_frame_in_one_frame_out_and_forced_idr_is_keyframe():
    frames = pattern(30)
    encoder = H264Encoder(176, 144, 25, 200)
    out = [encoder.encode(f, force_idr=(i == 20)) for i, f in enumerate(frames)]
    assert out[0].is_keyframe
    assert [o.is_keyframe for o in out[1:]].count(True) == 1 and out[20].is_keyframe
    # The forced IDR decodes on a fresh decoder, alone (in-band SPS/PPS).
    picture = H264Decoder().decode(out[20].data)
    assert picture is not None and picture.shape == (216, 176)
    assert psnr_db(frames[20][:144], picture[:144]) > 25


def test_decode_round_trip_quality_rises_with_rate():
    frames = pattern(25)
    psnrs = []
    for rate in (50, 800):
        encoder, decoder = H264Encoder(176, 144, 25, rate), H264Decoder()
        pics = [decoder.decode(encoder.encode(f).data) for f in frames]
        psnrs.append(
            np.mean([psnr_db(f[:144], p[:144]) for f, p in zip(frames, pics, strict=True)])
        )
    assert psnrs[1] > psnrs[0] + 3


def test_rung_change_to_new_size_decodes_on_same_decoder():
    decoder = H264Decoder()
    big = H264Encoder(352, 288, 25, 500)
    small = H264Encoder(176, 144, 12.5, 100)
    frames = pattern(4, 352, 288)
    assert decoder.decode(big.encode(frames[0]).data).shape == (432, 352)
    small_frame = resize_yuv420(frames[1], 176, 144)
    assert decoder.decode(small.encode(small_frame, force_idr=True).data).shape == (216, 176)


def test_corrupt_packet_gives_video_error_or_no_picture():
    decoder = H264Decoder()
    try:
        picture = decoder.decode(b"\x00\x00\x00\x01\x65" + bytes(range(256)) * 3)
    except VideoError as err:
        assert "corrupt" in str(err)
    else:
        assert picture is None or picture.dtype == np.uint8


def test_encoder_rejects_wrong_frames():
    encoder = H264Encoder(176, 144, 25, 100)
    with pytest.raises(VideoError, match="expected a"):
        encoder.encode(np.zeros((144, 176), dtype=np.uint8))
    with pytest.raises(VideoError, match="even"):
        H264Encoder(175, 144, 25, 100)


def test_resize_keeps_layout():
    frame = pattern(1, 352, 288)[0]
    small = resize_yuv420(frame, 176, 144)
    assert small.shape == (216, 176)
    assert abs(float(small[:144].mean()) - float(frame[:288].mean())) < 2
