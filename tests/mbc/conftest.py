import numpy as np
import pytest

from uma.face.talking_head import TalkingHeadSource


@pytest.fixture(scope="session")
def head() -> TalkingHeadSource:
    """The built-in talking head at CIF (ground truth exact)."""
    return TalkingHeadSource(352, 288, seed=3)


@pytest.fixture(scope="session")
def head_frames(head: TalkingHeadSource) -> list[np.ndarray]:
    """Its first 12 frames, gray, with sensor noise."""
    import cv2

    rng = np.random.default_rng(3)
    return [cv2.cvtColor(head.render_bgr(i, rng=rng), cv2.COLOR_BGR2GRAY) for i in range(12)]


@pytest.fixture(scope="session")
def stream_round_trip():
    """`round_trip(units, sent)`, see below."""
    return _stream_round_trip


def _stream_round_trip(units, sent: dict[int, np.ndarray]):
    """Push each frame's values of `sent` through a parameter stream of `units` and decode
    every packet: (packets, decoded values per frame, half a quantiser step per parameter)."""
    from uma.mbc import ParameterDecoder, ParameterEncoder, StreamConfig
    from uma.mbc.quant import Quantiser

    config = StreamConfig()
    encoder, decoder = ParameterEncoder(units, config), ParameterDecoder(units, config)
    packets = []
    for frame, values in sent.items():
        packets += encoder.push(frame, values)
    packets += encoder.flush()
    got = {}
    for packet in packets:
        got.update(decoder.decode(packet.to_bytes()).frames)
    steps = Quantiser(units.kinds, config.quantiser).steps(config.quantiser.global_code)
    return packets, got, 0.5 * steps * units.unit + 1e-9
