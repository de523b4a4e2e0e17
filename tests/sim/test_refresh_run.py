"""The model-aided refresh in a whole run: 3G into GPRS at QCIF, the engine on MBC with the
spare rate refreshing the receiver's reference, and the results reporting it."""

import numpy as np
import pytest

from uma.config.scenario import Scenario
from uma.sim import run_scenario
from uma.sim.summary import run_metrics


def scenario(refresh: bool, switching: str = "threshold") -> Scenario:
    return Scenario.model_validate(
        {
            "name": "gprs-refresh",
            "seed": 2,
            "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
            "route": [
                {"technology": "3G", "duration_s": 2.0},
                {"technology": "GPRS", "duration_s": 10.0},
            ],
            "engine": {
                "policy": "oracle",
                "switching": {"policy": switching, "min_dwell_ms": 1000.0},
                "mbc": {"refresh": {"enabled": refresh, "preset": "ultrafast"}},
            },
            "receiver": {"playout_delay_ms": 800.0},
            "metrics": {"ssim": False, "workers": 0},
        }
    )


# A whole run with the model codec takes several seconds: `make test-all` runs these.
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def refreshed():
    return run_scenario(scenario(True))


def test_the_spare_rate_refreshes_the_receiver_and_is_reported(refreshed):
    metrics = run_metrics(refreshed)
    assert metrics["codec_switches"] == 1
    assert metrics["refreshes"] >= 2 and metrics["refresh_intra"] >= 1
    assert metrics["refresh_decoded"] >= 2 and metrics["refresh_adopted"] >= 1
    assert metrics["refresh_lost"] == 0
    # Its bits are its own key, beside the parameters' (which stay the codec's own).
    log = refreshed.log
    mbc_rows = np.array([str(c) == "mbc" for c in log["codec"]])
    assert metrics["bits_sent"]["mbc"] == int(log["size_bits"][mbc_rows].sum()) > 0
    assert metrics["kbps_refresh"] > metrics["kbps_mbc"]
    duration_s = refreshed.duration_s
    assert metrics["refresh_bits"] == pytest.approx(
        metrics["kbps_refresh"] * duration_s * 1000, rel=1e-3
    )
    assert metrics["engine_refresh_compute_s"] > 0
    kinds = [event.kind for event in refreshed.events]
    assert kinds.count("refresh") == metrics["refreshes"]
    # Every refresh left after the switch to MBC (none while on H.264).
    switch_s = next(e.time_s for e in refreshed.events if e.kind == "codec_switch")
    assert all(e.time_s >= switch_s for e in refreshed.events if e.kind == "refresh")


def test_an_h264_only_run_reports_no_refresh():
    metrics = run_metrics(run_scenario(scenario(True, switching="none")))
    assert metrics["kbps_refresh"] == 0 and metrics["refreshes"] == 0
    # Refresh off: its keys are not there, so earlier results files read the same.
    assert "kbps_refresh" not in run_metrics(run_scenario(scenario(False, switching="none")))


# Not met since the MBC alone improved (issue 27): on this talking head (the model's own
# rendering) GPRS's face box gains 0.44 dB from the refresh (26.31 against 25.86; before the
# rate controller was wired in it lost 0.03-0.09 dB); akiyo from 3G into GPRS with adaptive
# playout gains 1.5 dB (22.12 against 20.63).
@pytest.mark.xfail(strict=True, reason="the refresh gains under 2 dB over the MBC alone here")
def test_the_refreshed_mbc_pictures_are_closer_to_the_source(refreshed):
    plain = run_scenario(scenario(False))

    def gprs_face_db(run):
        return run_metrics(run)["by_technology"]["GPRS"]["psnr_face_db"]

    log = refreshed.log
    codec = np.array([str(c) for c in log["codec"]])
    shown = log["shown_frame"].astype(int)
    mbc = (shown >= 0) & (codec[np.clip(shown, 0, None)] == "mbc")
    assert mbc.sum() > 100 and np.isfinite(log["psnr_face_db"][mbc]).all()
    assert gprs_face_db(refreshed) > gprs_face_db(plain) + 2.0
