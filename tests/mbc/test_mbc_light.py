"""Light in the parameter stream: estimated, coded, decoded within half a step, checked."""

import numpy as np
import pytest

from uma.mbc import FaceUnits, PacketError, ParameterDecoder, ParameterEncoder, StreamConfig
from uma.mbc.light import estimate_light
from uma.mbc.packets import parse_packet
from uma.mbc.quant import Quantiser


def test_estimate_light_recovers_gain_and_offset() -> None:
    rng = np.random.default_rng(0)
    rendered = rng.uniform(40, 200, (60, 80))
    mask = np.zeros((60, 80), bool)
    mask[10:50, 20:60] = True
    actual = 1.2 * rendered - 7.0
    gain, offset = estimate_light(rendered, actual, mask, every=1)
    assert gain == pytest.approx(1.2, abs=1e-6) and offset == pytest.approx(-7.0, abs=1e-4)
    assert estimate_light(np.full((60, 80), 90.0), actual, mask) == (1.0, 0.0)


def _units(head) -> FaceUnits:
    return FaceUnits.of(head.model, head.description.params, light=True)


def test_stream_round_trips_light_within_half_a_step(head) -> None:
    units = _units(head)
    config = StreamConfig()
    encoder, decoder = ParameterEncoder(units, config), ParameterDecoder(units, config)
    rng = np.random.default_rng(1)
    sent, packets = {}, []
    for frame in range(12):
        light = (1.0 + 0.2 * np.sin(frame / 3), 10.0 * np.cos(frame / 4) + rng.normal())
        params = np.concatenate([head.params_at(frame), light])
        sent[frame] = params
        packets += encoder.push(frame, params)
    packets += encoder.flush()
    assert all(p.light for p in packets)
    steps = Quantiser(units.kinds, config.quantiser).steps(config.quantiser.global_code)
    half = 0.5 * steps * units.unit + 1e-9
    got = {}
    for packet in packets:
        got.update(decoder.decode(packet.to_bytes()).frames)
    assert sorted(got) == list(range(12))
    for frame, params in got.items():
        assert np.all(np.abs(params[-2:] - sent[frame][-2:]) <= half[-2:])
        geometry, light = units.split(params)
        assert geometry.shape == head.params_at(0).shape and light is not None


def test_absurd_light_is_a_packet_error(head) -> None:
    units = _units(head)
    encoder, decoder = ParameterEncoder(units), ParameterDecoder(units)
    params = np.concatenate([head.params_at(0), (50.0, 0.0)])  # a gain of 50
    packets = encoder.push(0, params) + encoder.flush()
    with pytest.raises(PacketError, match="light gain"):
        decoder.decode(packets[0].to_bytes())
    assert decoder.params is None  # nothing absurd reached the screen


def test_light_flag_must_match_the_stream(head) -> None:
    plain = FaceUnits.of(head.model, head.description.params)
    encoder = ParameterEncoder(plain)
    packets = encoder.push(0, head.params_at(0)) + encoder.flush()
    assert not parse_packet(packets[0].to_bytes()).light
    with pytest.raises(PacketError, match="light absent"):
        ParameterDecoder(_units(head)).decode(packets[0].to_bytes())


def test_measured_light_of_a_relit_rendering() -> None:
    import cv2

    from uma.face.talking_head import Motion, TalkingHeadSource
    from uma.mbc.light import measure_light
    from uma.mbc.scene_render import SceneRenderer

    head = TalkingHeadSource(176, 144, seed=1, motion=Motion(noise_std=0.0, light_angle_rad=0.0))
    renderer = SceneRenderer(head.description, (176, 144))
    params = head.params_at(0)
    frame = cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420)[:144].astype(np.float64)
    relit = np.clip(1.1 * frame - 12.0, 0, 255)
    gain, offset = measure_light(renderer, relit, params)
    assert gain == pytest.approx(1.1, abs=0.03) and offset == pytest.approx(-12.0, abs=3.0)
