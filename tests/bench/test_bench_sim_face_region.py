"""`uma bench sim` replays the face-region rung through the same codec registry."""

from uma.bench.sim import SimBenchConfig, run_sim_bench
from uma.config.scenario import Scenario


def test_replay_covers_the_face_region_rung():
    scenario = Scenario.model_validate(
        {
            "name": "wlan-gsm-face",
            "seed": 1,
            "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
            "route": [
                {"technology": "WLAN", "duration_s": 1.0},
                {"technology": "GSM", "duration_s": 4.0},
            ],
            "engine": {"policy": "oracle", "face_region": {"enabled": True}},
            "receiver": {"playout_delay_ms": 800.0},
            "metrics": {"ssim": False},
        }
    )
    result = run_sim_bench(SimBenchConfig(scenario=scenario, frames=125, width=176, height=144))
    assert result["codecs"] == ["h264", "h264-face"]
    assert set(result["codec_s_by_codec"]) == {"h264", "h264-face"}
    assert result["codec_s_by_codec"]["h264-face"] > 0
