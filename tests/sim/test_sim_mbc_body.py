"""The model codec in a run sends the body motion and draws the layered scene with it; its
refresh is the bench's (`uma bench mbc`): one coder, one composition."""

import numpy as np
import pytest

from uma.config.codecs import MbcConfig, RefreshConfig
from uma.engine.refresh import RefreshOrder
from uma.sim.packets import EncodedUnit

SIZE = (176, 144)


@pytest.fixture(scope="module")
def head():
    import cv2

    from uma.face.talking_head import Motion, TalkingHeadSource

    source = TalkingHeadSource(*SIZE, seed=2, motion=Motion(noise_std=0.0))
    return source, cv2.cvtColor(source.render_bgr(0), cv2.COLOR_BGR2YUV_I420)


def _shifted(picture, dy_px):
    """The whole picture moved down by `dy_px` (even), edges repeated."""
    height = picture.shape[0] * 2 // 3
    luma = np.roll(picture[:height], dy_px, axis=0)
    luma[:dy_px] = luma[dy_px]
    chroma = np.roll(picture[height:].reshape(2, height // 2, -1), dy_px // 2, axis=1)
    return np.concatenate([luma, chroma.reshape(height // 2, -1)])


def _context(source, *, layered=True, refresh=False):
    from uma.mbc import StreamConfig

    mbc = MbcConfig(refresh=RefreshConfig(enabled=refresh, preset="ultrafast"))
    return {
        "description": source.description, "source_size": SIZE, "mbc": mbc, "fps": 25.0,
        "stream": StreamConfig(frames_per_packet=1), "layered": layered,
    }  # fmt: skip


def _encoder(context):
    from uma.sim.mbc_codecs import MbcPointEncoder

    return MbcPointEncoder(
        None, source_size=SIZE, source_fps=25.0, settings=None, context=context
    )  # fmt: skip


def test_the_engine_sends_the_torsos_motion_and_the_receiver_draws_it(head):
    from uma.sim.mbc_codecs import MbcUnitDecoder

    source, picture = head
    encoder = _encoder(_context(source))
    assert encoder.units.body and encoder.mirror is None
    assert encoder.initialise(picture, frame=0)
    moved = _shifted(picture, 6)
    coded = [encoder.encode(p, intra=i == 0, frame=i) for i, p in enumerate((picture, moved))]
    body = encoder.units.body_of(encoder.stream.decoded)
    assert abs(body[0]) < 1.0 and 4.5 < body[1] < 7.5 and abs(body[2]) < 0.02  # down 6 px
    decoder = MbcUnitDecoder(context=_context(source))
    shown = {}
    for i, unit in enumerate(coded):
        frames = unit.frames
        shown |= decoder.decode(EncodedUnit(i, frames[-1], "mbc", 0, *SIZE, i == 0, unit.data,
                                            frames))  # fmt: skip
    assert np.array_equal(decoder.units.body_of(decoder.values_by_frame[1]), body)
    # The torso drawn where it went: the rendering is nearer the moved picture than a still one.
    params, light = decoder.units.split(decoder.values_by_frame[1])
    still, _ = decoder.renderer.render(params, light, None)
    rows = slice(SIZE[1] * 3 // 4, SIZE[1])  # the shoulders
    error = [np.mean(np.abs(p[rows].astype(float) - moved[rows])) for p in (shown[1], still)]
    assert error[0] < error[1]


def test_the_stretched_scene_sends_no_body_motion(head):
    from uma.sim.mbc_codecs import MbcUnitDecoder

    source, _ = head
    context = _context(source, layered=False)
    assert not _encoder(context).units.body
    decoder = MbcUnitDecoder(context=context)
    assert not decoder.units.body and not decoder.renderer.layered


def test_an_absurd_body_motion_shows_the_last_good_picture(head):
    from uma.sim.mbc_codecs import MbcUnitDecoder

    source, _ = head
    decoder = MbcUnitDecoder(context=_context(source))
    params = source.description.params
    good = decoder._render(params, (1.0, 0.0), np.zeros(3)).copy()
    again = decoder._render(params, (1.0, 0.0), np.array([1e6, 0.0, 0.0]))
    assert np.array_equal(again, good)
    assert np.isfinite(again).all()


def test_an_absurd_body_motion_on_the_first_frame_shows_the_still_scene(head):
    """No good picture yet: the scene without the body motion, not an error or NaN."""
    from uma.sim.mbc_codecs import MbcUnitDecoder

    source, _ = head
    decoder = MbcUnitDecoder(context=_context(source))
    params = source.description.params
    shown = decoder._render(params, (1.0, 0.0), np.array([0.0, 0.0, 7.0]))
    still, _ = decoder.renderer.render(params, None, None)
    assert shown.dtype == np.uint8 and np.array_equal(shown, still)


def test_a_refresh_off_the_plate_or_a_lost_plate_keeps_a_good_picture(head):
    """A refresh box outside the picture is refused (the old reference stays); a lost plate
    draws from the reference; a refresh of another scene starts the plate again, with its
    reason."""
    from uma.sim.mbc_codecs import MbcUnitDecoder

    source, picture = head
    decoder = MbcUnitDecoder(context=_context(source))
    values = np.concatenate([source.description.params, np.zeros(3), [1.0, 0.0]])
    decoder.values_by_frame[3] = values
    before = decoder.renderer.reference.copy()
    assert not decoder.refresh(3, ((170, 0), picture[:48, :32]))
    assert decoder.refresh_frame == -1 and np.array_equal(decoder.renderer.reference, before)
    params = source.description.params
    decoder.renderer.plate.forget()
    shown = decoder._render(params, (1.0, 0.0), np.zeros(3))
    assert decoder.renderer.plate.reason == "plate lost" and shown.dtype == np.uint8
    assert np.array_equal(shown, decoder.renderer.reference)  # the reference, not grey
    decoder.renderer.set_reference(picture, params)
    dark = np.full_like(picture, 16)
    decoder.renderer.set_reference(dark, params)
    assert "started again" in decoder.renderer.plate.reason
    shown = decoder._render(params, (1.0, 0.0), np.zeros(3))
    assert np.array_equal(shown, dark)


def test_the_simulation_and_the_bench_code_one_refresh(head, monkeypatch):
    """The simulation's refresh (`uma.sim.refresh`, `uma.sim.mbc_codecs`) and the bench's
    (`uma.bench.mbc_refresh`) call the same coder and the same composition."""
    import uma.bench.mbc_refresh as bench
    import uma.mbc
    from uma.mbc import refresh_coder
    from uma.sim.mbc_codecs import MbcUnitDecoder
    from uma.sim.refresh import RefreshChain, RefreshDecoder

    assert bench.RefreshCoder is refresh_coder.RefreshCoder is uma.mbc.RefreshCoder
    assert bench.take_refresh is refresh_coder.take_refresh is uma.mbc.take_refresh
    calls = []

    class Spy(refresh_coder.RefreshCoder):
        def code(self, frame, corner=None):
            calls.append("code")
            return super().code(frame, corner)

    def take(*args):
        calls.append("take")
        return refresh_coder.take_refresh(*args)

    monkeypatch.setattr(uma.mbc, "RefreshCoder", Spy)
    monkeypatch.setattr(uma.mbc, "take_refresh", take)
    source, picture = head
    context = _context(source, refresh=True)
    encoder, decoder = _encoder(context), MbcUnitDecoder(context=context)
    chain = RefreshChain(context["mbc"].refresh, source_size=SIZE)
    assert encoder.initialise(picture, frame=0)
    unit = encoder.encode(picture, intra=True, frame=0)
    decoder.decode(EncodedUnit(0, 0, "mbc", 0, *SIZE, True, unit.data, unit.frames))
    data, intra, _ = chain.engine_code(encoder, picture, RefreshOrder(0, 16.0, 1.0, True))
    assert intra and calls == ["code"]
    assert chain.receiver_decode(decoder, 0, data) is not None and decoder.refresh_frame == 0
    assert chain.engine_adopt(encoder, 0) and encoder.refresh_frame == 0
    assert calls == ["code", "take", "take"]
    # Both ends paste the same box onto their own rendering (which differ before the first
    # refresh: the engine's is its initialisation picture): inside the feathered edge, equal.
    (x0, y0), patch = RefreshDecoder(source_size=SIZE).decode(data)
    height, width = patch.shape[0] * 2 // 3, patch.shape[1]
    inner = (slice(y0 + 8, y0 + height - 8), slice(x0 + 8, x0 + width - 8))
    assert np.array_equal(encoder.mirror.reference[inner], decoder.renderer.reference[inner])


def test_both_ends_keep_one_block_map_and_its_changes_ride_in_the_packets(head):
    """The engine draws each decoded set on its mirror and sends the map's changes in the
    set's packet; the receiver takes them into the same map (`BlockMap.step` at both ends)."""
    from uma.mbc import StreamConfig
    from uma.mbc.packets import parse_packet
    from uma.sim.mbc_codecs import MbcUnitDecoder

    source, picture = head
    context = _context(source) | {"stream": StreamConfig(frames_per_packet=4)}
    encoder, decoder = _encoder(context), MbcUnitDecoder(context=context)
    assert encoder.initialise(picture, frame=0)
    pictures = [picture] + [_shifted(picture, 2 * min(k, 4)) for k in range(1, 40)]
    flagged = 0
    for i, p in enumerate(pictures):
        unit = encoder.encode(p, intra=i == 0, frame=i)
        if unit.data:  # a packet every four frames
            flagged += parse_packet(unit.data).block_map
            decoder.decode(EncodedUnit(i, i, "mbc", 0, *SIZE, False, unit.data, unit.frames))
    sent, taken = encoder.map.block_map, decoder.block_map
    assert flagged and sent.changes > 0 and taken.changes == sent.changes
    assert taken.bits == sent.bits
    assert np.array_equal(taken.state, sent.state)
