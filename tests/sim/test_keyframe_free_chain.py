"""The codec chain retargets the open encoder on a rate change within a size: bits follow the
target, no IDR; a change of size, or an encoder deaf to its rate, is a new stream."""

from __future__ import annotations

import numpy as np
import pytest

from uma.engine.points import OperatingPoint, same_stream
from uma.sim.coder_factories import FullFramePointEncoder
from uma.video import NAL_IDR, H264Decoder, nal_unit_types
from uma.video.ladder import EncoderSettings

FPS = 25


def frames(n: int, width: int = 176, height: int = 144):
    """A moving noise pattern, planar YUV 4:2:0 (enough texture that the rate binds)."""
    rng = np.random.default_rng(2)
    base = rng.integers(0, 256, size=(height * 3 // 2, width + n), dtype=np.uint8)
    return [np.ascontiguousarray(base[:, i : i + width]) for i in range(n)]


def test_a_rate_change_within_a_size_retargets_without_an_idr_and_bits_follow():
    high = OperatingPoint("h264", 384.0, 25.0, 176, 144, compute_ms=4.0)
    low = OperatingPoint("h264", 128.0, 25.0, 176, 144, compute_ms=4.0)
    assert same_stream(high, low)
    encoder = FullFramePointEncoder(
        high, source_size=(176, 144), source_fps=FPS, settings=EncoderSettings(),
        span=(25.0, 384.0),
    )  # fmt: skip
    decoder = H264Decoder(conceal=False)
    sizes, keys = [], []
    for i, picture in enumerate(frames(4 * FPS)):
        if i == 2 * FPS:
            assert encoder.retarget(low)
        out = encoder.encode(picture, intra=False)
        assert decoder.decode(out.data) is not None
        sizes.append(8 * len(out.data))
        keys.append(out.keyframe or NAL_IDR in nal_unit_types(out.data))
    assert keys[0] and not any(keys[1:])  # the opening IDR only
    second = [sum(sizes[s * FPS : (s + 1) * FPS]) / 1000.0 for s in range(4)]
    assert 0.8 * 384 <= second[1] <= 1.05 * 384
    assert 0.8 * 128 <= second[3] <= 1.1 * 128


def test_another_size_or_codec_is_another_stream():
    cif = OperatingPoint("h264", 384.0, 25.0, 352, 288, compute_ms=4.0)
    qcif = OperatingPoint("h264", 128.0, 25.0, 176, 144, compute_ms=4.0)
    vp8 = OperatingPoint("vp8", 128.0, 25.0, 176, 144, compute_ms=4.0)
    mbc = OperatingPoint("mbc", 4.8, 25.0, 176, 144, compute_us_per_evaluation=260.0)
    assert not same_stream(cif, qcif) and not same_stream(qcif, vp8)
    assert not same_stream(mbc, mbc)  # only full-frame encoders are retargeted


@pytest.mark.parametrize("codec", ["vp8", "av1"])
def test_an_encoder_deaf_to_its_rate_says_so_and_is_reopened(codec):
    """libvpx and SVT-AV1 ignore a new rate through PyAV (docs/keyframe-free.md): `retarget`
    is falsy, so `EngineCoder` opens a new encoder (a keyframe) as before."""
    point = OperatingPoint(codec, 256.0, 25.0, 176, 144, compute_ms=4.0)
    other = OperatingPoint(codec, 128.0, 25.0, 176, 144, compute_ms=4.0)
    settings = _settings(codec)
    encoder = FullFramePointEncoder(
        point, source_size=(176, 144), source_fps=FPS, settings=settings, span=(25.0, 256.0)
    )
    assert not encoder.retarget(other)


def _settings(codec: str):
    from uma.codecs import spec
    from uma.paths import codecs_dir
    from uma.video import load_ladder

    return load_ladder(codecs_dir() / spec(codec).ladder).encoder
