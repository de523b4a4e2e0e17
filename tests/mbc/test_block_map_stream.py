"""The block map as the codec's: its changes in the packets, both ends calling `BlockMap.step`."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.face import load_model
from uma.mbc.block_map import BLOCK_PX, CHOICES, BlockMap, change_bits, count_bits
from uma.mbc.coding import MAP_CODES
from uma.mbc.decoder import ParameterDecoder
from uma.mbc.errors import PacketError, SceneError
from uma.mbc.packets import Packet, parse_packet
from uma.mbc.stream import ParameterEncoder, StreamConfig
from uma.mbc.units import FaceUnits

MODEL = load_model()
START = np.concatenate([[88.0, 72.0, 40.0, 0.0, 0.0, 0.0], np.zeros(MODEL.n_actions)])
UNITS = FaceUnits.of(MODEL, START)
CONFIG = StreamConfig(frames_per_packet=4, intra_period_frames=16)
SIZE = (176, 144)
FPS = 25.0


def _face(x0: int) -> np.ndarray:
    face = np.zeros(SIZE[::-1], bool)
    face[44:92, x0 : x0 + 44] = True  # reaches into blocks it does not fill
    return face


def test_the_flag_and_the_changes_round_trip_through_a_packet():
    assert len(CHOICES) - 1 == MAP_CODES
    encoder = ParameterEncoder(UNITS, CONFIG, map_blocks=256)
    changes = [np.array([[3, 1], [200, 3]]), None, np.array([[255, 0]]), np.zeros((0, 2))]
    packets = []
    for frame, sent in enumerate(changes):
        packets += encoder.push(frame, START, sent)
    (packet,) = packets
    assert packet.block_map and parse_packet(packet.to_bytes()).block_map
    decoder = ParameterDecoder(UNITS, CONFIG, map_blocks=256)
    out = decoder.decode(packet.to_bytes())
    assert [f for f, _ in out.frames] == [0, 1, 2, 3]
    for sent, got in zip(changes, out.changes, strict=True):
        expected = np.zeros((0, 2)) if sent is None else sent
        np.testing.assert_array_equal(got, expected.reshape(-1, 2))
    # A stream set up without the map refuses the packet (and the other way round).
    with pytest.raises(PacketError, match="block map present"):
        ParameterDecoder(UNITS, CONFIG).decode(packet.to_bytes())
    plain = ParameterEncoder(UNITS, CONFIG)
    plain_packets = [p for frame in range(4) for p in plain.push(frame, START)]
    assert not plain_packets[0].block_map
    assert plain_packets[0].to_bytes()[0] & 0xF0 == 0x10  # version 1, no map: the old layout


def test_the_map_costs_what_the_engine_counts():
    sizes = {}
    for blocks in (0, 256):
        encoder = ParameterEncoder(UNITS, StreamConfig(frames_per_packet=64), map_blocks=blocks)
        rng = np.random.default_rng(0)
        packets = []
        for frame in range(64):
            sent = np.stack([rng.choice(256, 3, replace=False), rng.integers(0, 4, 3)], 1)
            packets += encoder.push(frame, START, sent if blocks else None)
        packets += encoder.flush()
        sizes[blocks] = sum(len(p.words) for p in packets) * 32
    counted = 64 * (count_bits(3) + 3 * change_bits(256))
    assert abs(sizes[256] - sizes[0] - counted) <= 64  # the range coder's rounding: two words


def test_the_receiver_draws_exactly_what_the_engine_mirrored():
    rng = np.random.default_rng(1)
    width, height = SIZE
    engine, receiver = BlockMap(SIZE, FPS), BlockMap(SIZE, FPS)
    encoder = ParameterEncoder(UNITS, CONFIG, map_blocks=engine.map_blocks)
    decoder = ParameterDecoder(UNITS, CONFIG, map_blocks=receiver.map_blocks)
    truth = rng.integers(0, 256, (height * 3 // 2, width), dtype=np.uint8)
    plate = truth.copy()
    shown_engine, inputs = {}, {}
    for frame in range(12):
        rendering = truth.copy()
        rendering[: height // 2] = rng.integers(0, 256, (height // 2, width), dtype=np.uint8)
        face = _face(60 + frame % 3)
        inputs[frame] = (rendering, face)
        shown_engine[frame] = engine.step(rendering, face, plate, truth, truth[:height], 40.0)
        packets = encoder.push(frame, START, engine.sent)
        for packet in packets:
            out = decoder.decode(packet.to_bytes())
            for (f, _), changes in zip(out.frames, out.changes, strict=True):
                rendering, face = inputs[f]
                shown = receiver.step(rendering, face, plate, truth, changes=changes)
                np.testing.assert_array_equal(shown, shown_engine[f])
    assert engine.changes > 0 and receiver.changes == engine.changes
    assert receiver.bits == engine.bits and np.array_equal(receiver.state, engine.state)


def test_a_change_the_receiver_cannot_take_is_a_typed_error():
    receiver = BlockMap(SIZE, FPS)
    picture = np.zeros((SIZE[1] * 3 // 2, SIZE[0]), np.uint8)
    face = np.zeros(SIZE[::-1], bool)
    face[40 : 40 + 6 * BLOCK_PX, 56 : 56 + 6 * BLOCK_PX] = True
    window = receiver.window(face)
    cols = window[2] - window[0]
    inside = (40 // BLOCK_PX + 2 - window[1]) * cols + (56 // BLOCK_PX + 2 - window[0])
    with pytest.raises(SceneError, match="may not show the plate"):
        receiver.step(picture, face, picture, picture, changes=[(inside, 2)])  # the plate
    with pytest.raises(SceneError, match="without a face"):
        receiver.step(picture, np.zeros_like(face), picture, picture, changes=[(0, 0)])


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.integers(0, 2**32 - 1), min_size=1, max_size=12),
    st.booleans(),
    st.integers(1, 6),
)
def test_a_corrupt_map_field_decodes_or_raises_the_typed_error(words, intra, count):
    # A valid header and checksum around words no encoder wrote, with the map's flag.
    packet = Packet(seq=0, first_frame=0, count=count, intra=intra, global_code=16,
                    words=np.array(words, dtype=np.uint32), block_map=True)  # fmt: skip
    decoder = ParameterDecoder(UNITS, CONFIG, map_blocks=256)
    try:
        out = decoder.decode(packet.to_bytes())
    except PacketError:
        assert decoder.needs_intra
        return
    for changes in out.changes:
        assert len(changes) <= 256 and len(np.unique(changes[:, 0])) == len(changes)
        assert np.all((changes[:, 0] < 256) & (changes[:, 1] < MAP_CODES))


def test_a_packet_without_a_change_goes_without_the_map():
    mapped, plain = ParameterEncoder(UNITS, CONFIG, map_blocks=256), ParameterEncoder(UNITS, CONFIG)
    for frame in range(4):
        (got,) = mapped.push(frame, START, np.zeros((0, 2))) or [None]
        (want,) = plain.push(frame, START) or [None]
    assert not got.block_map and got.to_bytes() == want.to_bytes()  # not a bit spent
    out = ParameterDecoder(UNITS, CONFIG, map_blocks=256).decode(got.to_bytes())
    assert len(out.changes) == 4 and all(len(c) == 0 for c in out.changes)
