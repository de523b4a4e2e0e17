"""The model-aided refresh in the world: its coders (the engine's mirror is the receiver's
picture), the receiver's refresh chain, and the model codec's reference after a refresh, a
lost refresh and a corrupt one."""

import numpy as np
import pytest

from uma.config.codecs import MbcConfig, RefreshConfig
from uma.engine.decisions import DiscardRefresh, RefreshCoded
from uma.engine.refresh import RefreshOrder, RefreshPlanner
from uma.metrics.framelog import FrameLog
from uma.sim.packets import EncodedUnit, packetize
from uma.sim.receiver import ReceiverState
from uma.sim.refresh import FACE_SCALE, RefreshChain, RefreshDecoder, RefreshEncoder

SIZE = (176, 144)


@pytest.fixture(scope="module")
def head():
    import cv2

    from uma.face.talking_head import Motion, TalkingHeadSource

    source = TalkingHeadSource(*SIZE, seed=2, motion=Motion(noise_std=0.0))
    frames = {
        i: cv2.cvtColor(source.render_bgr(i), cv2.COLOR_BGR2YUV_I420)
        for i in (0, 6, 8, 10, 20, 30, 40)
    }
    return source, frames


def _units(source, *, body=False):
    from uma.mbc import FaceUnits

    return FaceUnits.of(source.model, source.description.params, light=True, body=body)


def _values(source, index, units):
    body = (0.0, 0.0, 0.0) if units.body else ()
    return np.concatenate([source.params_at(index), body, (1.0, 0.0)])


def _encode(encoder, source, frames, index, order, units):
    return encoder.encode(frames[index], order, source.model, _values(source, index, units), units)


def test_the_engines_mirror_is_exactly_what_the_receiver_decodes(head):
    source, frames = head
    config = RefreshConfig(enabled=True, preset="ultrafast")
    encoder = RefreshEncoder(config, source_size=SIZE)
    decoder = RefreshDecoder(source_size=SIZE)
    units = _units(source)
    sizes = []
    for i, index in enumerate((0, 10, 20)):
        order = RefreshOrder(index, 12.0, 1.0, intra=i == 0)
        data, intra = _encode(encoder, source, frames, index, order, units)
        assert intra == (i == 0)
        sizes.append(8 * len(data))
        (corner, patch), (kept_corner, kept_patch) = decoder.decode(data), encoder.kept[index][0]
        assert corner == kept_corner and np.array_equal(patch, kept_patch)
        assert patch.shape[1] == encoder.box[0] and patch.shape[0] == encoder.box[1] * 3 // 2
        assert encoder.coder.coded == tuple(int(v * FACE_SCALE) for v in encoder.box)
        assert np.array_equal(encoder.kept[index][1], _values(source, index, units))
    assert max(sizes) <= 1.1 * 12000  # about its bits a frame each, the VBV one frame
    assert encoder.taken(20) is not None and sorted(encoder.kept) == [20]
    assert decoder.decode(b"\x00\x00\x00\x00\x00\x00\x01\x65garbage") is None  # corrupt
    assert decoder.decode(b"\x00") is None  # too short to carry a corner


class Clock:
    t = 0.0

    def __call__(self):
        return self.t


def _refresh_unit(seq, frame, data, key):
    return EncodedUnit(seq, frame, "mbc", 0, SIZE[0], SIZE[1], key, data, refresh=True)


def test_a_lost_refresh_leaves_the_reference_and_asks_for_an_intra_one(head):
    source, frames = head
    config = RefreshConfig(enabled=True, preset="ultrafast")
    encoder = RefreshEncoder(config, source_size=SIZE)
    taken = []
    clock, requests = Clock(), []
    decoder = RefreshDecoder(source_size=SIZE)

    def decode_refresh(unit):
        picture = decoder.decode(unit.data)
        if picture is not None:
            taken.append(unit.frame)
        return picture

    receiver = ReceiverState(
        log=FrameLog(50), decode=lambda unit: {}, request_keyframe=requests.append, now=clock,
        decode_refresh=decode_refresh, refresh_frame=lambda: taken[-1] if taken else -1,
    )  # fmt: skip
    seq = 0

    def send(refresh_seq, index, *, intra, drop=()):
        nonlocal seq
        order = RefreshOrder(index, 12.0, 1.0, intra)
        data, key = _encode(encoder, source, frames, index, order, _units(source))
        packets = packetize(_refresh_unit(refresh_seq, index, data, key), first_seq=seq,
                            payload_bytes=200, sent_s=clock.t)  # fmt: skip
        seq += len(packets)
        for packet in packets:
            if packet.index not in drop:
                receiver.on_packet(packet)

    send(0, 0, intra=True)
    assert taken == [0] and requests == []
    send(1, 10, intra=False, drop=(0,))  # a packet lost: the refresh never completes
    send(2, 20, intra=False)  # the chain is broken: not decoded, an intra one asked for
    assert taken == [0] and receiver.refresh_received.lost == 1
    assert [r.refresh for r in requests] == [True]
    assert receiver.make_report(0.1).refresh_frame == 0  # still the last good one
    send(3, 30, intra=True)
    assert taken == [0, 30] and receiver.make_report(0.1).refresh_frame == 30
    assert 30 not in receiver.decoded  # a box alone is nothing to show (the model codec's is)


def test_the_model_codecs_receiver_renders_from_each_refresh_taken(head):
    from uma.mbc import ParameterEncoder, StreamConfig
    from uma.sim.mbc_codecs import MbcUnitDecoder

    source, frames = head
    mbc = MbcConfig(refresh=RefreshConfig(enabled=True, preset="ultrafast", face="picture"))
    context = {
        "description": source.description, "source_size": SIZE, "mbc": mbc,
        "stream": StreamConfig(frames_per_packet=4), "background": frames[0],
    }  # fmt: skip
    decoder = MbcUnitDecoder(context=context)
    chain = RefreshChain(mbc.refresh, source_size=SIZE)
    units = decoder.units
    assert units.body  # the layered scene: the body motion travels with the face
    stream = ParameterEncoder(units, context["stream"], decoder.block_map.map_blocks)
    packets = []
    for i in range(1, 13):
        packets += stream.push(i, _values(source, i, units))
    sets = {}
    for seq, packet in enumerate(packets):
        carried = tuple(range(packet.first_frame, packet.first_frame + packet.count))
        unit = EncodedUnit(seq, carried[-1], "mbc", 0, *SIZE, packet.intra, packet.to_bytes(),
                           carried)  # fmt: skip
        decoder.decode(unit)
        sets.update({f: decoder.values_by_frame[f] for f in carried})
    order = RefreshOrder(6, 16.0, 1.0, True)
    data, _ = chain.encoder.encode(frames[6], order, source.model, sets[6], units)
    before = decoder.renderer.reference.copy()
    shown = chain.receiver_decode(decoder, 6, data)
    assert decoder.refresh_frame == 6 and np.array_equal(shown, decoder.renderer.reference)
    assert np.array_equal(decoder.renderer.reference_params, units.split(sets[6])[0])
    assert not np.array_equal(decoder.renderer.reference, before)
    # The engine's mirror takes the same refresh the same way: the same reference.
    from uma.sim.mbc_codecs import MbcPointEncoder

    engine = MbcPointEncoder.__new__(MbcPointEncoder)
    engine.units, engine.mirror = units, None
    engine.description, engine.mbc, engine.layered = source.description, mbc, True
    engine.width, engine.height = SIZE
    engine.set_reference(frames[0], units.split(sets[1])[0])
    assert chain.engine_adopt(engine, 6) and engine.refresh_frame == 6
    # (The mirror draws luma only: everything the engine decides with it reads luma.)
    assert engine.mirror.luma_only and not decoder.renderer.luma_only
    height = SIZE[1]
    assert np.array_equal(engine.mirror.reference[:height], decoder.renderer.reference[:height])
    # A corrupt refresh unit changes nothing: the last good reference stays.
    kept = decoder.renderer.reference.copy()
    assert chain.receiver_decode(decoder, 9, b"\x00\x00\x00\x00\x00\x00\x01\x65\xff" * 40) is None
    assert decoder.refresh_frame == 6 and np.array_equal(decoder.renderer.reference, kept)
    # A refresh whose pose is still to come waits for it; one whose pose was lost is let go.
    box = chain.encoder.kept.get(6, (((0, 0), frames[40][:48, :32]), None))[0]
    assert not decoder.refresh(40, box)
    assert decoder.refresh_frame == 6 and decoder.refresh_waiting[0] == 40
    del decoder.values_by_frame[8]
    assert not decoder.refresh(8, box)
    assert decoder.refresh_waiting is None and decoder.refresh_frame == 6


def test_the_face_comes_from_the_refresh_while_it_is_recent():
    from uma.sim.mbc_codecs import face_from_description

    def mbc(face):
        return MbcConfig(refresh=RefreshConfig(face=face, face_recent_ms=2000.0))

    assert face_from_description(mbc("recent"), 100, -1, 25.0)  # no refresh yet
    assert not face_from_description(mbc("recent"), 150, 100, 25.0)  # 2 s: still recent
    assert face_from_description(mbc("recent"), 151, 100, 25.0)
    assert not face_from_description(mbc("picture"), 1000, 100, 25.0)
    assert face_from_description(mbc("description"), 100, 100, 25.0)
    assert face_from_description(None, 100, 100, 25.0)


def test_a_refresh_no_better_than_the_receivers_picture_is_not_sent(head):
    from types import SimpleNamespace

    source, frames = head
    config = RefreshConfig(enabled=True, preset="ultrafast", min_gain_db=0.5)
    units = _units(source)
    params = source.params_at(10)

    def encoder_showing(picture):
        mirror = SimpleNamespace(render=lambda p, light, body=None, **_: (picture, None))
        stream = SimpleNamespace(decoded=np.append(params, (1.0, 0.0)))
        return SimpleNamespace(
            mirror=mirror, stream=stream, units=units, description=source.description,
            decoded_params=lambda: params, refresh_frame=0,
        )  # fmt: skip

    order = RefreshOrder(10, 8.0, 1.0, True)
    chain = RefreshChain(config, source_size=SIZE)
    # The coder measures the gain; the engine's planner decides (`min_gain_db`).
    plan = RefreshPlanner(config)

    def worth(coded):
        report = RefreshCoded(10, None, len(coded[0]), coded[1], coded[2])
        return not any(isinstance(a, DiscardRefresh) for a in plan.on_coded(report, 0.4))

    # The receiver already shows the frame itself: an 8 kbit refresh cannot beat it.
    coded = chain.engine_code(encoder_showing(frames[10]), frames[10], order)
    assert not worth(coded)
    chain.discard(10)
    assert chain.encoder.coder is None and 10 not in chain.encoder.kept  # next: intra
    # It shows an old picture of another pose: the refresh is sent, and starts intra.
    coded = chain.engine_code(encoder_showing(frames[40]), frames[10], order)
    assert worth(coded) and coded[1] is True and coded[2] > 0.5
    # Before the receiver took a refresh, the mirror is not its picture: the check is against
    # the receiver's own (the last picture it decoded, at the stream's first pose); sent when
    # that is not known yet, or when the first refresh of a stretch always goes.
    first = encoder_showing(frames[40])
    first.refresh_frame, first.first_params, first.mbc = -1, params, None
    assert not worth(chain.engine_code(first, frames[10], order, receiver_picture=frames[10]))
    assert worth(chain.engine_code(first, frames[10], order, receiver_picture=None))
    always = RefreshChain(config.model_copy(update={"first_always": True}), source_size=SIZE)
    assert worth(always.engine_code(first, frames[10], order, receiver_picture=frames[10]))


def test_the_run_summary_says_what_the_refresh_sent():
    from uma.sim.summary import format_summary

    metrics = {
        "scenario": "s", "seed": 1, "frames": 10, "video": "176x144@25", "source": "x",
        "switches": 0, "handovers": 0, "keyframe_requests": 0, "kbps_mbc": 0.6,
        "shown_s_by_codec": {"mbc": 1.0}, "switching": "threshold",
    }  # fmt: skip
    assert "refresh" not in format_summary(metrics, "out")
    metrics |= {"kbps_refresh": 1.747, "refreshes": 16, "refresh_intra": 2, "refresh_adopted": 12}
    line = [x for x in format_summary(metrics, "out").splitlines() if "refresh" in x]
    assert line == ["  refresh   1.747 kbit/s beside the model codec, 16 refreshes (2 intra), "
                    "12 taken by the receiver"]  # fmt: skip


def test_the_receivers_renderer_takes_engine_mbc_ring_sizes(head):
    from uma.sim.mbc_codecs import scene_renderer

    description = head[0].description
    default = scene_renderer(description, SIZE, MbcConfig())
    wider = scene_renderer(description, SIZE, MbcConfig(head_ring_outlines=1.8))
    farther = scene_renderer(description, SIZE, MbcConfig(far_ring_head_radii=2.5))
    assert np.array_equal(
        default.scene.head_ring, scene_renderer(description, SIZE).scene.head_ring
    )
    assert not np.array_equal(default.scene.head_ring, wider.scene.head_ring)
    assert not np.array_equal(default.scene.far_ring_px, farther.scene.far_ring_px)
