"""`uma bench mbc`'s refresh display: refresh pictures serve only after their bits arrived."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest


@dataclass
class _Pose:
    """The tracker's answer on a frame, here its ground truth."""

    params: np.ndarray

    def __bool__(self) -> bool:
        return True


@pytest.fixture(scope="module")
def head_clip():
    import cv2

    from uma.bench.mbc import ClipSpec
    from uma.face.talking_head import TalkingHeadSource

    source = TalkingHeadSource(176, 144, seed=2)
    frames = [
        cv2.cvtColor(source.render_bgr(i), cv2.COLOR_BGR2YUV_I420) for i in range(0, 60, 3)
    ]  # every third frame: more motion between refreshes
    results = [_Pose(source.params_at(i)) for i in range(0, 60, 3)]
    return ClipSpec("head", frames, 25.0, source.description), results


def _display(head_clip, spec, mbc_kbps):
    from uma.bench.mbc_refresh import refresh_display
    from uma.mbc.stream import StreamConfig
    from uma.mbc.units import FaceUnits

    clip, results = head_clip
    units = FaceUnits.of(clip.description.model, clip.description.params, light=True)
    return refresh_display(clip, results, units, StreamConfig(), mbc_kbps, spec)


def test_the_refresh_serves_from_its_arrival_and_adds_its_bits(head_clip) -> None:
    from uma.bench.mbc_refresh import RefreshSpec

    spec = RefreshSpec(0, 5.0, choose=False)  # every refresh picture adopted
    plain, plain_kbps, plain_info = _display(head_clip, spec, mbc_kbps=100.0)  # nothing left
    shown, kbps, info = _display(head_clip, spec, mbc_kbps=2.0)
    assert plain_info["units"] == 0 and plain_info["refresh_kbps"] == 0.0
    assert info["units"] == 4 and 1 <= info["served"] <= 4
    assert info["delay_frames_median"] >= 1  # never on its own frame: its bits take time
    assert kbps == pytest.approx(info["params_kbps"] + info["refresh_kbps"], abs=2e-3)
    assert kbps > plain_kbps + 5.0 and info["budget_kbps"] == pytest.approx(14.0)
    first = next(i for i, (a, b) in enumerate(zip(plain, shown, strict=True)) if not (a == b).all())
    assert first >= 1 + int(info["delay_frames_max"] > 0)  # frame 0's unit arrives later
    # Units that arrive after the clip's end never serve: the display is the plain MBC's.
    late_spec = RefreshSpec(0, 5.0, latency_s=10.0, choose=False)
    late, _, late_info = _display(head_clip, late_spec, mbc_kbps=2.0)
    assert late_info["served"] == 0 and late_info["units"] == 4
    assert all((a == b).all() for a, b in zip(plain, late, strict=True))


def test_the_encoder_keeps_a_reference_better_than_the_refresh(head_clip) -> None:
    """At ground-truth poses the rendering from the exact frame 0 often beats a 128x96 H.264
    picture upscaled: the encoder does not adopt every refresh picture, and only adopted ones
    serve; their bits are sent all the same."""
    from uma.bench.mbc_refresh import RefreshSpec

    _, _, info = _display(head_clip, RefreshSpec(0, 5.0), mbc_kbps=2.0)
    assert info["units"] == 4 and info["adopted"] < 4 and info["served"] <= info["adopted"]
    assert info["refresh_kbps"] > 5.0


def test_a_face_box_pasted_back_on_its_own_picture_changes_nothing_and_is_feathered() -> None:
    from uma.mbc.refresh_coder import _crop, _paste

    rng = np.random.default_rng(0)
    frame = rng.integers(0, 255, (96 * 3 // 2, 128), dtype=np.uint8)
    box = _crop(frame, 20, 10, 48, 32)
    assert box.shape == (48, 48) and np.array_equal(box[:32], frame[10:42, 20:68])
    assert np.array_equal(_paste(frame, box, 20, 10), frame)
    white = np.full_like(box, 255)
    pasted = _paste(np.zeros_like(frame), white, 20, 10)
    assert pasted[26, 44] == 255 and 0 < pasted[10, 44] < 64  # inside full, edge blended
    assert pasted[9, 44] == 0 and pasted[:96].sum() > 0
    assert pasted[96:].any()  # chroma pasted too


@pytest.mark.parametrize("intra", [False, True])
def test_a_residual_refresh_serves_every_adopted_unit_in_order_at_both_ends(
    head_clip, intra
) -> None:
    """A residual adds to the rendering from the reference before it: the receiver takes
    every adopted unit, in order, and ends on the engine mirror's very picture."""
    from uma.bench.mbc_refresh import RefreshSpec

    plain, _, _ = _display(head_clip, RefreshSpec(0, 5.0, choose=False), mbc_kbps=100.0)
    spec = RefreshSpec(0, 5.0, region="residual", face_scale=0.5, intra_every_unit=intra)
    shown, kbps, info = _display(head_clip, spec, mbc_kbps=2.0)
    assert info["units"] == 4 and info["region"] == "residual"
    assert 1 <= info["served"] <= info["adopted"] <= 4
    assert info["mirror_is_receiver"]
    assert kbps > 5.0 and info["delay_frames_median"] >= 1
    assert any(not (a == b).all() for a, b in zip(plain, shown, strict=True))


def test_the_default_refresh_codes_at_the_simulations_preset_and_intra_on_request(
    head_clip,
) -> None:
    """The bench's refresh box is coded at libx264's medium preset, as the simulation's
    `engine.mbc.refresh.preset` default; `intra_every_unit` makes every unit an IDR."""
    from dataclasses import replace

    from uma.bench.mbc_refresh import DEFAULT_REFRESH, _coder
    from uma.config.codecs import RefreshConfig

    clip, results = head_clip
    spec = DEFAULT_REFRESH["mbc_refresh_lowest"]
    coder, corners = _coder(clip, results, spec, 12.0, (176, 144))
    assert coder.encoder.preset == RefreshConfig().preset == "medium"
    assert coder.box is not None and len(corners) == len(results)
    intra, _ = _coder(clip, results, replace(spec, intra_every_unit=True), 12.0, (176, 144))
    frames = [clip.frames[i] for i in (0, 5, 10)]
    assert all(intra.code(f, corners[0])[1] for f in frames)
    assert [coder.code(f, corners[0])[1] for f in frames] == [True, False, False]


def test_a_refresh_spec_names_its_codec_and_the_rate_it_asks_for(head_clip) -> None:
    """`RefreshSpec.codec` codes with that codec's encoder at its ladder's settings (SVT-AV1
    at least 64 px a side), `rate_gain` scales the rate asked of it over the budget, and the
    default asks the budget itself, of libx264, with a VBV of 2 frames at 12.5 frames/s."""
    from dataclasses import replace

    from uma.bench.mbc_refresh import DEFAULT_REFRESH, _coder
    from uma.video import AV1Encoder, H264Encoder

    clip, results = head_clip
    spec = DEFAULT_REFRESH["mbc_refresh_second"]
    coder, _ = _coder(clip, results, spec, 12.0, (176, 144))
    assert isinstance(coder.encoder, H264Encoder) and coder.encoder.rate_kbps == 12.0
    assert coder.encoder.vbv_frames == 2.0 and spec.refresh_fps == 12.5
    av1 = replace(spec, codec="av1", preset=8, vbv_frames=1.0, rate_gain=0.8)
    coder, corners = _coder(clip, results, av1, 12.0, (176, 144))
    try:
        assert isinstance(coder.encoder, AV1Encoder) and coder.encoder.preset == 8
        assert abs(coder.encoder.rate_kbps - 9.6) < 1e-9 and min(coder.coded) >= 64
        bits, key, (corner, patch) = coder.code(clip.frames[0], corners[0])
        assert key and bits > 32 and patch.shape[1] == coder.box[0]
    finally:
        coder.close()
