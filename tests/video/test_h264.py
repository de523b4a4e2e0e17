import numpy as np
import pytest

from uma.errors import VideoError
from uma.metrics.quality import psnr_db
from uma.video import (
    NAL_IDR,
    H264Decoder,
    H264Encoder,
    PatternSource,
    RawYuvSource,
    VideoFileSource,
    load_ladder,
    nal_unit_types,
    resize_yuv420,
)


@pytest.fixture(scope="module")
def akiyo(shared_data):
    return list(VideoFileSource(shared_data / "faces" / "video" / "akiyo.mp4").frames())


@pytest.fixture(scope="module")
def foreman(shared_data):
    path = shared_data / "faces" / "video" / "foreman_part_qcif.yuv"
    return list(RawYuvSource(path, 176, 144, 25).frames())


def at_rung(frames, width, height, fps, source_fps=25.0):
    step = max(1, int(round(source_fps / fps)))
    return [resize_yuv420(f, width, height) for f in frames[::step]]


def steady_kbps(sizes_bits, fps):
    """Mean rate after the first second, which carries the opening IDR."""
    skip = int(round(fps))
    return sum(sizes_bits[skip:]) / ((len(sizes_bits) - skip) / fps) / 1000.0


def peak_queue_kbit(sizes_bits, rate_kbps, fps):
    """Largest backlog of a link draining at exactly `rate_kbps` (a leaky bucket)."""
    drain, level, worst = rate_kbps * 1000.0 / fps, 0.0, 0.0
    for size in sizes_bits:
        level += size
        worst = max(worst, level)
        level = max(0.0, level - drain)
    return worst / 1000.0


# Error of the steady rate against the target on akiyo (300 CIF frames, 12 s), measured with
# this libx264 (PyAV 18 wheel), VBV of 4 frame intervals, at the rungs of codecs/h264.yaml:
# 16k -14.7 %, 24k -10.3 %, 40k -7.0 %, 64k -6.3 %, 128k -4.5 %, 256k -4.3 %, 384k -5.2 %,
# 768k -4.5 %, 1200k -3.5 %. Never over: with maxrate = target libx264 undershoots, most on a
# still scene at 5 frames/s where it has nothing to spend bits on. Bounds leave ~4 points for
# other libx264 builds.
def tolerance(rate_kbps):
    return (0.80, 1.02) if rate_kbps < 32 else (0.90, 1.02)


def test_encoder_hits_every_ladder_rate_on_akiyo(akiyo):
    errors = {}
    for rung in load_ladder().rungs:
        frames = at_rung(akiyo, rung.width, rung.height, rung.fps)
        encoder = H264Encoder(rung.width, rung.height, rung.fps, rung.rate_kbps)
        got = steady_kbps([encoder.encode(f).size_bits for f in frames], rung.fps)
        errors[rung.label] = round(100 * (got / rung.rate_kbps - 1), 1)
        low, high = tolerance(rung.rate_kbps)
        assert low <= got / rung.rate_kbps <= high, errors


@pytest.mark.parametrize("rate_kbps, fps", [(40, 25 / 3), (128, 25.0)])
def test_encoder_rate_on_foreman_yuv(foreman, rate_kbps, fps):
    # measured -6.6 % (40k) and -4.1 % (128k) on the 48 frames looped 4 times
    frames = at_rung(foreman * 4, 176, 144, fps)
    encoder = H264Encoder(176, 144, fps, rate_kbps)
    got = steady_kbps([encoder.encode(f).size_bits for f in frames], fps)
    assert 0.88 * rate_kbps <= got <= 1.02 * rate_kbps, got


def test_encoder_rate_on_pattern_without_shared_data():
    # measured -5.4 % at QCIF 128k and -8.5 % at CIF 384k (seed 0, 8 s)
    for width, height, rate_kbps in ((176, 144, 128), (352, 288, 384)):
        frames = list(PatternSource(width, height, seed=0, frame_count=200).frames())
        encoder = H264Encoder(width, height, 25, rate_kbps)
        got = steady_kbps([encoder.encode(f).size_bits for f in frames], 25)
        assert 0.86 * rate_kbps <= got <= 1.02 * rate_kbps, (width, got)


@pytest.mark.parametrize("rate_kbps, width, height, fps", [(24, 176, 144, 5), (384, 352, 288, 25)])
def test_vbv_bounds_the_queue_at_the_target_rate(akiyo, rate_kbps, width, height, fps):
    # IDRs included (the first frame and one forced every 37): the backlog of a link at the
    # target rate stays within the VBV buffer (measured at 0.85 and 0.93 of it)
    frames = at_rung(akiyo, width, height, fps)
    encoder = H264Encoder(width, height, fps, rate_kbps)
    sizes = [encoder.encode(f, force_idr=i % 37 == 0).size_bits for i, f in enumerate(frames)]
    assert encoder.vbv_bufsize_kbit == int(4 * rate_kbps / fps)
    assert peak_queue_kbit(sizes, rate_kbps, fps) <= encoder.vbv_bufsize_kbit


def test_vbv_caps_the_opening_idr(akiyo):
    # measured: 3.4 frame budgets with the default 4-frame buffer, 4.5 with 12 frames
    budget_bits = 384_000 / 25
    small = H264Encoder(352, 288, 25, 384).encode(akiyo[0]).size_bits
    large = H264Encoder(352, 288, 25, 384, vbv_frames=12).encode(akiyo[0]).size_bits
    assert small <= 4 * budget_bits < large


def pattern(n, width=176, height=144, seed=2):
    return list(PatternSource(width, height, seed=seed, frame_count=n).frames())


def test_one_frame_in_one_frame_out_and_idr_only_where_asked():
    frames = pattern(30)
    encoder = H264Encoder(176, 144, 25, 200, keyint_frames=250)
    out = [encoder.encode(f, force_idr=i == 20) for i, f in enumerate(frames)]
    assert [o.pts for o in out] == list(range(30))
    idr = [i for i, o in enumerate(out) if NAL_IDR in nal_unit_types(o.data)]
    assert idr == [0, 20]
    assert [i for i, o in enumerate(out) if o.is_keyframe] == [0, 20]
    assert all(nal_unit_types(o.data) == [1] for i, o in enumerate(out) if i not in idr)
    assert out[5].size_bits == 8 * len(out[5].data)


def test_forced_idr_carries_headers_and_decodes_alone():
    frames = pattern(25)
    encoder = H264Encoder(176, 144, 25, 200)
    out = [encoder.encode(f, force_idr=i == 20) for i, f in enumerate(frames)]
    assert nal_unit_types(out[20].data)[:2] == [7, 8]  # SPS, PPS in band
    picture = H264Decoder().decode(out[20].data)
    assert picture.shape == (216, 176)
    assert psnr_db(frames[20][:144], picture[:144]) > 32  # measured 38.2 dB


def test_keyint_frames_sets_the_idr_period():
    encoder = H264Encoder(176, 144, 25, 200, keyint_frames=10)
    out = [encoder.encode(f) for f in pattern(25)]
    assert [i for i, o in enumerate(out) if o.is_keyframe] == [0, 10, 20]


def test_encoding_is_deterministic():
    frames = pattern(15)
    runs = [[H264Encoder(176, 144, 25, 100)] for _ in range(2)]
    a, b = ([run[0].encode(f).data for f in frames] for run in runs)
    assert a == b


def test_decode_round_trip_on_akiyo(akiyo):
    # measured 43.8 dB (CIF, 384 kbit/s) and 38.4 dB (QCIF, 64 kbit/s, 12.5 frames/s)
    for width, height, fps, rate_kbps, floor_db in (
        (352, 288, 25, 384, 42),
        (176, 144, 12.5, 64, 35),
    ):
        frames = at_rung(akiyo[:100], width, height, fps)
        encoder, decoder = H264Encoder(width, height, fps, rate_kbps), H264Decoder()
        pictures = [decoder.decode(encoder.encode(f).data) for f in frames]
        assert all(p.shape == f.shape for p, f in zip(pictures, frames, strict=True))
        mean_db = np.mean(
            [psnr_db(f[:height], p[:height]) for f, p in zip(frames, pictures, strict=True)]
        )
        assert mean_db > floor_db


def test_quality_rises_with_rate():
    frames = pattern(25)  # measured 31.5 dB at 50 kbit/s, 57.6 dB at 800
    psnrs = []
    for rate in (50, 800):
        encoder, decoder = H264Encoder(176, 144, 25, rate), H264Decoder()
        pictures = [decoder.decode(encoder.encode(f).data) for f in frames]
        psnrs.append(
            np.mean([psnr_db(f[:144], p[:144]) for f, p in zip(frames, pictures, strict=True)])
        )
    assert psnrs[1] > psnrs[0] + 3


def test_rung_change_to_a_new_size_decodes_on_the_same_decoder():
    decoder = H264Decoder()
    frames = pattern(6, 352, 288)
    big, small = H264Encoder(352, 288, 25, 500), H264Encoder(176, 144, 12.5, 100)
    assert decoder.decode(big.encode(frames[0]).data).shape == (432, 352)
    first_small = small.encode(resize_yuv420(frames[1], 176, 144))
    assert first_small.is_keyframe  # a new encoder starts with an IDR
    assert decoder.decode(first_small.data).shape == (216, 176)
    assert decoder.decode(small.encode(resize_yuv420(frames[2], 176, 144)).data).shape == (216, 176)
    back = H264Encoder(352, 288, 25, 500)
    picture = decoder.decode(back.encode(frames[3]).data)
    assert picture.shape == (432, 352) and psnr_db(frames[3][:288], picture[:288]) > 25


def test_garbage_and_empty_units_raise_video_error_and_the_decoder_recovers():
    out = [H264Encoder(176, 144, 25, 200).encode(f) for f in pattern(2)]
    decoder = H264Decoder()
    junk = bytes(np.random.default_rng(0).integers(0, 256, 500, dtype=np.uint8))
    with pytest.raises(VideoError, match="corrupt bitstream"):
        decoder.decode(junk)
    with pytest.raises(VideoError, match="empty access unit"):
        decoder.decode(b"")
    try:
        decoder.decode(out[1].data)  # a P-frame with no reference picture: FFmpeg's choice
    except VideoError as err:
        assert "corrupt bitstream" in str(err)
    assert decoder.decode(out[0].data).shape == (216, 176)  # the next IDR decodes
    assert decoder.decode(out[1].data).shape == (216, 176)


def test_truncated_idr_is_concealed_or_refused():
    frames = pattern(2)
    idr = H264Encoder(176, 144, 25, 200).encode(frames[0]).data
    truncated = idr[: len(idr) // 2]
    decoder = H264Decoder()
    picture = decoder.decode(truncated)
    assert picture.shape == (216, 176) and decoder.concealed_frames == 1
    assert psnr_db(frames[0][:144], picture[:144]) < psnr_db(
        frames[0][:144], H264Decoder().decode(idr)[:144]
    )
    with pytest.raises(VideoError, match="concealment"):
        H264Decoder(conceal=False).decode(truncated)


def test_encoder_rejects_bad_frames_and_settings():
    encoder = H264Encoder(176, 144, 25, 100)
    with pytest.raises(VideoError, match="expected a"):
        encoder.encode(np.zeros((144, 176), dtype=np.uint8))
    with pytest.raises(VideoError, match="expected a"):
        encoder.encode(np.zeros((216, 176), dtype=np.float32))
    with pytest.raises(VideoError, match="even"):
        H264Encoder(175, 144, 25, 100)
    with pytest.raises(VideoError, match="zerolatency"):
        H264Encoder(176, 144, 25, 100, tune="film")
    with pytest.raises(VideoError, match="preset"):
        H264Encoder(176, 144, 25, 100, preset="fastest")
    with pytest.raises(VideoError, match="positive fps"):
        H264Encoder(176, 144, 0, 100)


def test_nal_unit_types_parses_annex_b():
    assert nal_unit_types(b"\x00\x00\x00\x01\x67ab\x00\x00\x01\x68c\x00\x00\x01\x65") == [7, 8, 5]
    assert nal_unit_types(b"") == []


def test_vbv_settings_are_whole_kbit_x264_accepts():
    # x264 refuses "vbv-maxrate=1500.000" ("Error parsing option") and truncates it; whole kbit
    # rounded down keep the cap at or below the target
    encoder = H264Encoder(176, 144, 7.5, 37.9)
    assert (encoder.vbv_maxrate_kbit, encoder.vbv_bufsize_kbit) == (37, 20)
    assert "vbv-maxrate=37:vbv-bufsize=20:" in encoder.x264_params
