"""Full-frame codecs other than H.264 through the seam: `engine.codec` selects one, its bits
are counted under its own name, and its run goes through the same engine and world."""

import pytest

import uma.video
from uma.codecs import REGISTRY, Role, full_frame_names
from uma.config.scenario import Scenario
from uma.metrics.aggregate import aggregate, codec_bits
from uma.metrics.framelog import FrameLog

OTHERS = [name for name in full_frame_names() if name != "h264"]


def scenario(codec: str, **engine) -> Scenario:
    return Scenario.model_validate(
        {
            "name": f"{codec}-run",
            "seed": 2,
            "source": {"kind": "pattern", "width": 176, "height": 144, "fps": 25},
            "route": [
                {"technology": "3G", "duration_s": 2.0},
                {"technology": "GPRS", "duration_s": 2.0},
            ],
            "engine": {"codec": codec} | engine,
            "metrics": {"ssim": False, "workers": 0},
        }
    )


@pytest.mark.parametrize("codec", OTHERS)
def test_a_registered_full_frame_codec_may_be_selected(codec):
    assert scenario(codec).engine.codec == codec


def test_a_codec_that_is_not_full_frame_is_refused():
    with pytest.raises(ValueError, match="full-frame codec, one of h264"):
        scenario("h264-face")
    with pytest.raises(ValueError, match="full-frame codec"):
        scenario("mpeg2")


@pytest.mark.parametrize("codec", OTHERS)
def test_its_bits_are_counted_under_its_name(codec):
    log = FrameLog(4)
    log["codec"][:] = [codec, codec, "h264", ""]
    log["size_bits"][:] = [1000, 3000, 500, 0]
    bits = codec_bits(log)
    assert bits[codec] == 4000 and bits["h264"] == 500
    assert str(log["codec"][0]) == codec  # the column holds the name whole
    out = aggregate(log, duration_s=1.0, capacity_bits=1e4, link={"bits_delivered": 0},
                    event_kinds=[])  # fmt: skip
    assert out[f"kbps_{codec}"] == 4.0 and out["bits_sent"][codec] == 4000


def test_unused_codecs_that_earlier_results_never_had_stay_out():
    log = FrameLog(2)
    log["codec"][:] = ["h264", "h264"]
    assert list(codec_bits(log)) == [n for n, s in REGISTRY.items() if s.always_reported]


@pytest.mark.parametrize("codec", OTHERS)
def test_a_short_run_codes_every_sent_frame_with_it(codec):
    if not hasattr(uma.video, REGISTRY[codec].video_encoder):
        pytest.skip(f"uma.video has no {REGISTRY[codec].video_encoder} in this checkout")
    from uma.sim import run_scenario
    from uma.sim.summary import run_metrics

    result = run_scenario(scenario(codec))
    codecs = {str(c) for c in result.log["codec"]} - {""}
    assert codecs == {codec}
    assert {p.codec for p in result.points} == {codec}
    metrics = run_metrics(result)
    assert metrics[f"kbps_{codec}"] > 0 and metrics["kbps_h264"] == 0
    assert metrics["frames_decoded"] > 0.5 * metrics["frames_sent"]


def test_region_rungs_code_with_their_own_codec_in_another_codecs_run():
    from dataclasses import replace

    from uma.sim.codecs import CodecChain
    from uma.video import EncoderSettings, load_ladder

    other = OTHERS[0]
    run = scenario(other)
    h264 = load_ladder()  # the project's H.264 ladder
    # The run's ladder, with settings unlike the H.264 ladder's (its own codec's would be).
    fake = replace(h264, encoder=EncoderSettings(keyint_frames=99))
    assert fake.encoder != h264.encoder
    chain = CodecChain(run, fake, (), width=176, height=144, fps=25.0)
    assert chain.settings(other) is fake.encoder
    assert chain.settings("h264-face") == h264.encoder
    assert REGISTRY["h264-face"].role is Role.REGION
    assert chain.settings("mbc") is fake.encoder  # it takes none
