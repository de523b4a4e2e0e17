"""Parameter stream: encoder and decoder agree exactly; losses and corruption resynchronise."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.errors import UmaError
from uma.face import load_model
from uma.mbc.decoder import ParameterDecoder
from uma.mbc.errors import PacketError
from uma.mbc.packets import Packet, parse_packet
from uma.mbc.stream import ParameterEncoder, StreamConfig
from uma.mbc.units import FaceUnits

MODEL = load_model()
START = np.concatenate([[176.0, 144.0, 70.0, 0.0, 0.0, 0.0], np.zeros(MODEL.n_actions)])
UNITS = FaceUnits.of(MODEL, START)
CONFIG = StreamConfig(frames_per_packet=4, intra_period_frames=16)


def _track(frames: int, seed: int = 0) -> np.ndarray:
    """A smooth head motion with speech-like action units."""
    rng = np.random.default_rng(seed)
    t = np.arange(frames)[:, None] / 25.0
    params = np.tile(START, (frames, 1))
    params[:, 0] += 8 * np.sin(2 * np.pi * 0.1 * t[:, 0])
    params[:, 1] += 4 * np.sin(2 * np.pi * 0.13 * t[:, 0])
    params[:, 2] *= 1 + 0.03 * np.sin(2 * np.pi * 0.05 * t[:, 0])
    params[:, 3:6] += 0.1 * np.sin(2 * np.pi * np.array([0.2, 0.13, 0.17]) * t)
    params[:, 6:] += 0.3 * np.abs(np.sin(2 * np.pi * 3 * t + rng.uniform(0, 6, MODEL.n_actions)))
    return params


def _encode(params: np.ndarray, config: StreamConfig = CONFIG):
    encoder = ParameterEncoder(UNITS, config)
    packets, decoded = [], []
    for frame, p in enumerate(params):
        packets += encoder.push(frame, p)
        decoded.append(encoder.decoded)
    packets += encoder.flush()
    return packets, np.array(decoded)


def test_decoder_reproduces_the_encoders_quantised_values_exactly() -> None:
    params = _track(60)
    packets, expected = _encode(params)
    assert [p.count for p in packets] == [4] * 15
    assert [p.intra for p in packets] == [k % 4 == 0 for k in range(15)]
    decoder = ParameterDecoder(UNITS, CONFIG)
    got = {}
    for packet in packets:
        out = decoder.decode(packet.to_bytes())
        assert out.events == ()
        got.update(dict(out.frames))
    assert sorted(got) == list(range(60))
    assert np.array_equal(np.array([got[k] for k in range(60)]), expected)
    # Within half a step of the unquantised parameters, in every unit.
    steps = UNITS.from_units(
        ParameterEncoder(UNITS, CONFIG).quantiser.steps(CONFIG.quantiser.global_code)
    )
    assert np.all(np.abs(expected - params) <= steps / 2 + 1e-9)


def test_a_lost_packet_freezes_until_the_next_intra_set() -> None:
    packets, expected = _encode(_track(48))
    decoder = ParameterDecoder(UNITS, CONFIG)
    got = {}
    kinds = []
    for k, packet in enumerate(packets):
        if k == 1:
            continue  # lost
        out = decoder.decode(packet.to_bytes())
        kinds += [e.kind for e in out.events]
        got.update(dict(out.frames))
    assert kinds == ["missing", "waiting", "waiting", "resync"]
    # Frames 4-15 are gone (the lost packet and the two predicted from it); 16 on are exact.
    assert sorted(got) == list(range(4)) + list(range(16, 48))
    assert np.array_equal(np.array([got[k] for k in range(16, 48)]), expected[16:])


def test_corrupted_truncated_duplicated_and_reordered_packets_are_reported() -> None:
    packets, expected = _encode(_track(48))
    decoder = ParameterDecoder(UNITS, CONFIG)
    decoder.decode(packets[0].to_bytes())
    on_screen = decoder.params.copy()
    damaged = bytearray(packets[1].to_bytes())
    damaged[9] ^= 0x10
    with pytest.raises(PacketError, match="checksum"):
        decoder.decode(bytes(damaged))
    with pytest.raises(PacketError, match="truncated|checksum"):
        decoder.decode(packets[1].to_bytes()[:7])
    assert np.array_equal(decoder.params, on_screen)  # the last parameters stay
    assert decoder.decode(packets[0].to_bytes()).events[0].kind == "duplicate"
    out = decoder.decode(packets[2].to_bytes())  # packet 1 never arrived intact
    assert [e.kind for e in out.events] == ["missing", "waiting"] and not out.frames
    assert decoder.needs_intra
    assert decoder.decode(packets[1].to_bytes()).events[0].kind == "late"
    decoder.decode(packets[3].to_bytes())
    out = decoder.decode(packets[4].to_bytes())  # intra
    assert [e.kind for e in out.events] == ["resync"]
    assert np.array_equal(out.frames[-1][1], expected[19])


def test_intra_on_request_and_after_a_frame_without_parameters() -> None:
    params = _track(20)
    encoder = ParameterEncoder(UNITS, CONFIG)
    packets = []
    for frame in range(6):
        packets += encoder.push(frame, params[frame])
    encoder.request_intra()
    for frame in range(6, 12):
        packets += encoder.push(frame, params[frame])
    packets += encoder.push(12, None)  # the tracker lost the face
    for frame in range(13, 20):
        packets += encoder.push(frame, params[frame])
    packets += encoder.flush()
    layout = [(p.first_frame, p.count, p.intra) for p in packets]
    assert layout == [
        (0, 4, True),
        (4, 4, False),
        (8, 4, True),  # requested at frame 6: the next packet starts intra
        (13, 4, True),  # after the frame without parameters
        (17, 3, False),
    ]


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=80))
def test_arbitrary_bytes_give_the_typed_error_or_decode_cleanly(data: bytes) -> None:
    decoder = ParameterDecoder(UNITS, CONFIG)
    try:
        out = decoder.decode(data)
    except PacketError as err:
        assert isinstance(err, UmaError) and isinstance(err, ValueError)
        assert "MBC packet 0" in str(err)
        return
    for _, params in out.frames:
        assert np.all(np.isfinite(params))


_GOOD = [p.to_bytes() for p in _encode(_track(24))[0]]


@settings(max_examples=300, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.integers(0, len(_GOOD) - 1),
            st.sampled_from(["keep", "flip", "cut", "garbage"]),
            st.integers(0, 10_000),
        ),
        max_size=12,
    )
)
def test_damaged_streams_then_an_intra_packet_resynchronise(ops) -> None:
    decoder = ParameterDecoder(UNITS, CONFIG)
    for index, how, salt in ops:
        data = bytearray(_GOOD[index])
        if how == "flip":
            data[salt % len(data)] ^= 1 << (salt % 8)
        elif how == "cut":
            data = data[: salt % len(data)]
        elif how == "garbage":
            data = bytearray(np.random.default_rng(salt).integers(0, 256, salt % 64, np.uint8))
        try:
            out = decoder.decode(bytes(data))
        except PacketError:
            continue
        for _, params in out.frames:
            assert np.all(np.isfinite(params)) and params[2] > 0
    # A fresh intra packet, whatever came before, decodes to the encoder's values.
    packets, expected = _encode(_track(24))
    tail = packets[4]  # the second intra packet (frames 16-19)
    renumbered = Packet(
        seq=(parse_packet(_GOOD[-1]).seq + 7) % 65536,
        first_frame=tail.first_frame,
        count=tail.count,
        intra=True,
        global_code=tail.global_code,
        words=tail.words,
    )
    out = decoder.decode(renumbered.to_bytes())
    assert np.array_equal(out.frames[-1][1], expected[19])


@settings(max_examples=300, deadline=None)
@given(
    st.lists(st.integers(0, 2**32 - 1), max_size=12),
    st.booleans(),
    st.integers(1, 8),
    st.integers(1, 255),
)
def test_well_formed_packets_with_random_payloads_decode_or_raise_the_typed_error(
    words, intra, count, code
) -> None:
    # A valid header and checksum around words no encoder wrote: the range decoder must not
    # let anything but `PacketError` or finite parameters with a positive scale out.
    packet = Packet(
        seq=0,
        first_frame=0,
        count=count,
        intra=intra,
        global_code=code,
        words=np.array(words, dtype=np.uint32),
    )
    decoder = ParameterDecoder(UNITS, CONFIG)
    try:
        out = decoder.decode(packet.to_bytes())
    except PacketError:
        assert decoder.needs_intra
        return
    for _, params in out.frames:
        assert np.all(np.isfinite(params)) and params[2] > 0
