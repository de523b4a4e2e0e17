"""`uma bench mbc`'s refresh receiver decodes the units it receives with its own decoder."""

from __future__ import annotations

import numpy as np

from tests.bench.test_bench_mbc_refresh import _display, head_clip  # noqa: F401 (a fixture)


def test_the_receiver_decodes_every_unit_it_receives_itself(head_clip, monkeypatch) -> None:  # noqa: F811
    """Two decoders decode the refresh stream: the engine's (every unit, as coded) and the
    receiver's (every unit that arrived, in order); the receiver takes exactly the engine's
    decoded pictures of the units it is served."""
    import uma.bench.mbc_refresh_receiver as receiving
    import uma.mbc.refresh_coder as coding
    from uma.bench.mbc_refresh import RefreshSpec
    from uma.video import H264Decoder

    calls: dict[int, int] = {}
    decode = H264Decoder.decode

    def counted(self, data):
        calls[id(self)] = calls.get(id(self), 0) + 1
        return decode(self, data)

    engine_pictures, taken = [], []
    code = coding.RefreshCoder.code

    def coded(self, frame, corner=None, base=None):
        out = code(self, frame, corner, base)
        engine_pictures.append(out[2])
        return out

    take = receiving.take_refresh

    def took(renderer, units, values, picture):
        taken.append(picture)
        return take(renderer, units, values, picture)

    monkeypatch.setattr(H264Decoder, "decode", counted)
    monkeypatch.setattr(coding.RefreshCoder, "code", coded)
    monkeypatch.setattr(receiving, "take_refresh", took)
    spec = RefreshSpec(0, 5.0, region="face", face_scale=0.5, choose=False)
    _, _, info = _display(head_clip, spec, mbc_kbps=2.0)
    assert info["units"] == 4 and info["served"] >= 1 and len(taken) == info["served"]
    engine, receiver = list(calls.values())  # two decoders, the engine's first
    assert engine == 4 and info["served"] <= receiver <= 4
    for corner, patch in taken:
        same = [p for p in engine_pictures if p[0] == corner and np.array_equal(p[1], patch)]
        assert same and all(p is not patch for p in engine_pictures)  # equal, not handed over
