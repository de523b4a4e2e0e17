"""Helpers the VP8 and AV1 tests share: frames, the steady rate, the mean PSNR of a round trip."""

import numpy as np
import pytest

from uma.errors import VideoError
from uma.metrics.quality import psnr_db
from uma.video import PatternSource, resize_yuv420


def pattern(n, width=176, height=144, seed=2):
    return list(PatternSource(width, height, seed=seed, frame_count=n).frames())


def steady_kbps(sizes_bits, fps):
    """Mean rate after the first second, which carries the opening key frame."""
    skip = int(round(fps))
    return sum(sizes_bits[skip:]) / ((len(sizes_bits) - skip) / fps) / 1000.0


def round_trip_psnr_db(encoder, decoder, frames):
    """Mean luma PSNR of `frames` encoded and decoded in order; every picture has its shape."""
    height = frames[0].shape[0] * 2 // 3
    scores = []
    for frame in frames:
        picture = decoder.decode(encoder.encode(frame).data)
        assert picture.shape == frame.shape and picture.dtype == np.uint8
        scores.append(psnr_db(frame[:height], picture[:height]))
    return float(np.mean(scores))


def forced_key_frames(encoder, count=10, forced=6):
    """Encode `count` pattern frames forcing a key frame at `forced`; check one packet each."""
    frames = pattern(count, encoder.width, encoder.height)
    out = [encoder.encode(f, force_idr=i == forced) for i, f in enumerate(frames)]
    assert [o.pts for o in out] == list(range(count))
    assert [i for i, o in enumerate(out) if o.is_keyframe] == [0, forced]
    return frames, out


def check_key_frame_decodes_alone(encoder, decoder, floor_db):
    frames, out = forced_key_frames(encoder, 8, 6)
    picture = decoder.decode(out[6].data)
    assert picture.shape == frames[6].shape
    assert psnr_db(frames[6][: encoder.height], picture[: encoder.height]) > floor_db


def check_deterministic(make_encoder):
    frames = pattern(8)
    a, b = (
        [encoder.encode(f).data for f in frames] for encoder in (make_encoder(), make_encoder())
    )
    assert a == b


def check_rung_change(encoder_class, decoder):
    """A new encoder at a new size starts with a key frame the same decoder follows."""
    frames = pattern(2, 352, 288)
    big = encoder_class(352, 288, 25, 500).encode(frames[0])
    assert decoder.decode(big.data).shape == (432, 352)
    small = encoder_class(176, 144, 12.5, 100).encode(resize_yuv420(frames[1], 176, 144))
    assert small.is_keyframe and decoder.decode(small.data).shape == (216, 176)


def check_garbage_then_recovery(encoder, decoder):
    out = [encoder.encode(f) for f in pattern(2)]
    junk = bytes(np.random.default_rng(0).integers(0, 256, 500, dtype=np.uint8))
    try:
        decoder.decode(junk)
    except VideoError as err:
        assert "corrupt bitstream" in str(err)
    with pytest.raises(VideoError, match="empty packet"):
        decoder.decode(b"")
    assert decoder.decode(out[0].data).shape == (216, 176)
    assert decoder.decode(out[1].data).shape == (216, 176)


def check_bad_frames_and_sizes(encoder_class):
    with pytest.raises(VideoError, match="expected a"):
        encoder_class(176, 144, 25, 100).encode(np.zeros((144, 176), dtype=np.uint8))
    with pytest.raises(VideoError, match="even"):
        encoder_class(175, 144, 25, 100)
    with pytest.raises(VideoError, match="positive fps"):
        encoder_class(176, 144, 0, 100)


def check_rate_near_target(encoder, frames, low=0.93, high=1.05):
    """The rate after the first second within [low, high] of the encoder's target."""
    got = steady_kbps([encoder.encode(f).size_bits for f in frames], encoder.fps)
    assert low * encoder.rate_kbps <= got <= high * encoder.rate_kbps, got


def check_quality_rises(make_encoder, decoder_class, rates=(60, 600), gain_db=3.0):
    low, high = (
        round_trip_psnr_db(make_encoder(rate), decoder_class(), pattern(15)) for rate in rates
    )
    assert high > low + gain_db, (low, high)
