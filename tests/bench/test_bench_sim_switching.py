"""`uma bench sim` replays a switching run through the same codec registry: every codec timed."""

import pytest

from uma.bench.sim import SimBenchConfig, run_sim_bench
from uma.config.scenario import Scenario


# GSM long enough for the scheme to be on MBC for a while (adaptation switches ~2.5 s in).
@pytest.mark.parametrize("scheme, gsm_s", [("adaptation", 3.2), ("selection", 1.0)])
def test_replay_covers_every_codec_the_run_used(scheme, gsm_s):
    scenario = Scenario.model_validate(
        {
            "name": "wlan-gsm",
            "seed": 1,
            "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
            "route": [
                {"technology": "WLAN", "duration_s": 0.4},
                {"technology": "GSM", "duration_s": gsm_s},
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
    frames = round((0.4 + gsm_s) * 25)
    result = run_sim_bench(SimBenchConfig(scenario=scenario, frames=frames, width=176, height=144))
    assert result["codecs"] == ["h264", "mbc"]
    assert set(result["codec_s_by_codec"]) == {"h264", "mbc"}
    assert result["codec_s_by_codec"]["mbc"] > 0 and result["codec_s_by_codec"]["h264"] > 0
    assert result["codec_s"] > 0 and result["ratio"] > 0
