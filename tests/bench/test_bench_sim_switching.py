"""`uma bench sim` replays a switching run through the same codec registry: every codec timed."""

import pytest

from uma.bench.sim import SimBenchConfig, run_sim_bench
from uma.config.scenario import Scenario


@pytest.mark.parametrize("scheme", ["adaptation", "selection"])
def test_replay_covers_every_codec_the_run_used(scheme):
    scenario = Scenario.model_validate(
        {
            "name": "wlan-gsm",
            "seed": 1,
            "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
            "route": [
                {"technology": "WLAN", "duration_s": 1.0},
                {"technology": "GSM", "duration_s": 4.0},
            ],
            "engine": {
                "policy": "oracle",
                "switching": {"policy": "threshold"},
                "mbc": {"scheme": scheme},
            },
            "receiver": {"playout_delay_ms": 800.0},
            "metrics": {"ssim": False},
        }
    )
    result = run_sim_bench(SimBenchConfig(scenario=scenario, frames=125, width=176, height=144))
    assert result["codecs"] == ["h264", "mbc"]
    assert set(result["codec_s_by_codec"]) == {"h264", "mbc"}
    assert result["codec_s_by_codec"]["mbc"] > 0 and result["codec_s_by_codec"]["h264"] > 0
    assert result["codec_s"] > 0 and result["ratio"] > 0
