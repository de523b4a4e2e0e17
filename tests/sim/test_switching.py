"""A short route WLAN, GSM, WLAN: the engine switches to the model-based codec and back.

The oracle's budget (the true capacity) makes the switch instants known, so the test can check
the whole chain: initialisation on the engine's picture (H.264 keeps flowing meanwhile), MBC
units decoded and rendered at the receiver, the return to H.264 with a new reference chain,
and every source frame accounted for.
"""

import numpy as np
import pytest

from uma.config.scenario import Scenario
from uma.sim import run_scenario

ROUTE = [
    {"technology": "WLAN", "duration_s": 3.0},
    {"technology": "GSM", "duration_s": 6.0},
    {"technology": "WLAN", "duration_s": 4.0},
]


def scenario(**engine):
    return Scenario.model_validate(
        {
            "name": "wlan-gsm-wlan",
            "seed": 1,
            "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
            "route": ROUTE,
            "engine": {"policy": "oracle"} | engine,
            # GSM's one-way delay is 250 ms: at the default 300 ms deadline any codec is late.
            "receiver": {"playout_delay_ms": 800.0},
            "metrics": {"ssim": False, "workers": 0},
        }
    )


@pytest.fixture(scope="module")
def switched():
    return run_scenario(scenario(switching={"policy": "threshold", "min_dwell_ms": 1000.0}))


def test_switches_to_mbc_in_gsm_and_back_in_wlan(switched):
    events = [(e.time_s, e.kind, e.detail) for e in switched.events]
    kinds = [k for _, k, _ in events]
    switches = [(t, d.split()[0]) for t, k, d in events if k == "codec_switch"]
    assert [d for _, d in switches] == ["h264->mbc", "mbc->h264"]
    init_start = next(t for t, k, _ in events if k == "mbc_init_start")
    init_done = next(t for t, k, _ in events if k == "mbc_init_done")
    assert 3.0 <= init_start < 3.6  # right after the handover gap into GSM
    assert init_start < init_done <= switches[0][0]  # the MBC point only once initialised
    assert 9.0 <= switches[1][0] < 10.0  # back soon after GSM ends
    assert "mbc_init_failed" not in kinds


def test_every_frame_is_accounted_for(switched):
    log = switched.log
    n = log.frames
    assert n == 13 * 25
    sent = log["sent"].astype(bool)
    scheduled = log["scheduled"].astype(bool)
    decoded = log["decoded"].astype(bool)
    codec = np.array([str(c) for c in log["codec"]])
    # Sent frames are scheduled ones, and say their codec; unsent ones none.
    assert np.all(scheduled[sent])
    assert set(codec[sent]) == {"h264", "mbc"} and set(codec[~sent]) <= {""}
    assert np.all(sent[decoded])  # only what was sent is decoded
    # Every display instant shows a decoded frame not newer than itself, or nothing yet.
    shown = log["shown_frame"].astype(int)
    assert np.all(shown <= np.arange(n))
    assert np.all((shown == -1) | decoded[np.clip(shown, 0, None)])
    # MBC only inside GSM (plus the frames in flight at the handover back).
    tech = np.array([str(t) for t in log["technology"]])
    mbc = codec == "mbc"
    assert mbc.sum() > 100 and np.all(tech[mbc] != "") and (tech[mbc] == "GSM").mean() > 0.9
    assert decoded[mbc].mean() > 0.9  # parameters fit GSM's 9.6 kbit/s
    # Frames were H.264 while the initialisation ran: none missing between the two codecs.
    first_mbc = int(np.flatnonzero(mbc)[0])
    assert codec[first_mbc - 1] in ("h264", "")


def test_mbc_keeps_the_gsm_display_alive(switched):
    h264_only = run_scenario(scenario())
    tech = np.array([str(t) for t in switched.log["technology"]])
    gsm = tech == "GSM"
    frozen_switching = switched.log["frozen"][gsm].mean()
    frozen_h264 = h264_only.log["frozen"][gsm].mean()
    assert frozen_h264 > 0.6  # GSM: the lowest rung (16 kbit/s) does not fit 9.6
    assert frozen_switching < 0.1
    psnr = switched.log["psnr_db"][gsm & (switched.log["codec"] == "mbc")]
    assert np.isfinite(psnr).all() and np.median(psnr) > 12.0  # a face was rendered


def test_no_description_stays_on_the_lowest_rung_and_completes():
    base = scenario(switching={"policy": "threshold"})
    pattern = base.source.model_copy(update={"kind": "pattern"})
    run = run_scenario(base.model_copy(update={"source": pattern}))
    refused = [e for e in run.events if e.kind == "mbc_refused"]
    assert refused and "no content description" in refused[0].detail
    codec = np.array([str(c) for c in run.log["codec"]])
    assert "mbc" not in set(codec)
    tech = np.array([str(t) for t in run.log["technology"]])
    rungs = run.log["rung"][(tech == "GSM") & run.log["sent"].astype(bool)]
    assert rungs.size and np.all(rungs[-5:] == 0)


def test_no_face_when_the_switch_is_due_stays_on_the_lowest_rung(tmp_path):
    # A description of the talking head, but a source with no face in it: every
    # initialisation fails, the engine says why, keeps H.264's lowest rung and completes.
    from uma.face import TalkingHeadSource

    path = tmp_path / "head.npz"
    TalkingHeadSource(width=176, height=144, fps=25, seed=1).description.save(path)
    base = scenario(
        switching={"policy": "threshold", "retry_ms": 2000.0}, mbc={"description": str(path)}
    )
    pattern = base.source.model_copy(update={"kind": "pattern"})
    run = run_scenario(base.model_copy(update={"source": pattern}))
    failed = [e for e in run.events if e.kind == "mbc_init_failed"]
    assert failed and "initialisation failed" in failed[0].detail
    assert 3 <= len(failed) <= 4  # retried every 2 s while the budget is low (3 to 9.5 s)
    codec = np.array([str(c) for c in run.log["codec"]])
    assert "mbc" not in set(codec)
    tech = np.array([str(t) for t in run.log["technology"]])
    rungs = run.log["rung"][(tech == "GSM") & run.log["sent"].astype(bool)]
    assert rungs.size and np.all(rungs[-3:] == 1)  # the lowest H.264 rung, after the MBC point


def test_predictive_policy_is_on_mbc_before_the_boundary():
    run = run_scenario(
        scenario(switching={"policy": "predictive", "lookahead_ms": 1000.0, "min_dwell_ms": 500.0})
    )
    events = {e.kind: e.time_s for e in reversed(run.events)}  # the first of each kind
    assert 1.9 <= events["mbc_init_start"] < 2.1  # 1 s before GSM begins at 3.0 s
    switch = next(e for e in run.events if e.kind == "codec_switch")
    assert switch.detail.startswith("h264->mbc") and switch.time_s < 3.0
    codec = np.array([str(c) for c in run.log["codec"]])
    tech = np.array([str(t) for t in run.log["technology"]])
    sent = run.log["sent"].astype(bool)
    assert np.all(codec[sent & (tech == "GSM")] == "mbc")


def test_description_delivery_under_a_tiny_capacity_delays_the_first_switch():
    # Straight into GSM: MBC is wanted at once, but the receiver needs the description
    # first; its chunks cannot arrive faster than 9.6 kbit/s carries them, and the lowest
    # H.264 rung keeps flowing beside them (backlog-limited), so slower than that.
    from uma.sim.packets import HEADER_BYTES

    # 20 s of GSM: the description is acknowledged at about 17.3 s and the switch follows.
    base = scenario(switching={"policy": "threshold", "min_dwell_ms": 0.0})
    gsm = base.route[1].model_copy(update={"duration_s": 20.0})
    run = run_scenario(base.model_copy(update={"route": (gsm,)}))
    chunks = -(-run.description.size_bytes // base.downlink.packet_bytes)
    fastest_s = 8 * chunks * (base.downlink.packet_bytes + HEADER_BYTES) / 9600.0
    assert fastest_s <= run.description.delivered_s <= 2.5 * fastest_s
    assert run.description.acked_s > run.description.delivered_s  # a report carried the news
    events = [(e.time_s, e.kind) for e in run.events]
    waiting = next(t for t, k in events if k == "mbc_waiting_description")
    assert waiting < 0.1
    first_init = next(t for t, k in events if k == "mbc_init_start")
    first_switch = next(t for t, k in events if k == "codec_switch")
    assert run.description.acked_s <= first_init < first_switch < 20.0
    assert run.description.wait_s == pytest.approx(run.description.acked_s - waiting)
    codec = np.array([str(c) for c in run.log["codec"]])
    assert np.all(codec[: int(run.description.acked_s * 25)] != "mbc")


def test_selection_scheme_moves_the_tracking_to_the_sender(switched):
    # Adaptation: the engine tracks (and initialises on the switch); selection: the sender
    # tracks every frame and sends the parameters up, the engine only selects and re-codes.
    # `switched` is the adaptation run (the default scheme).
    def run(scheme):
        switching = {"policy": "threshold", "min_dwell_ms": 1000.0}
        return run_scenario(scenario(switching=switching, mbc={"scheme": scheme}))

    from uma.sim.summary import run_metrics

    assert switched.scenario == scenario(
        switching={"policy": "threshold", "min_dwell_ms": 1000.0}, mbc={"scheme": "adaptation"}
    )
    selection_run = run("selection")
    adaptation, selection = run_metrics(switched), run_metrics(selection_run)
    assert adaptation["scheme"] == "adaptation" and selection["scheme"] == "selection"
    assert adaptation["kbps_uplink_mbc"] == 0 and adaptation["sender_mbc_ms_per_frame"] == 0
    # Every source frame's parameters go up: about 25 packets/s of 12 bytes and a few words.
    assert 2.5 < selection["kbps_uplink_mbc"] < 6.0
    assert selection["sender_mbc_ms_per_frame"] > 1.0
    # The engine's MBC compute falls to coding and the light alone (`encode_ms` + `light_ms`
    # a frame): no tracking, no initialisation fit.
    mbc = selection_run.scenario.engine.mbc
    coded = int(np.count_nonzero(selection_run.log["codec"] == "mbc"))
    per_frame_s = (mbc.encode_ms + mbc.light_ms) / 1000.0
    assert selection["engine_mbc_compute_s"] == pytest.approx(coded * per_frame_s, rel=0.05)
    assert selection["engine_mbc_compute_s"] < 0.25 * adaptation["engine_mbc_compute_s"]
    for metrics in (adaptation, selection):
        assert metrics["codec_switches"] == 2 and metrics["kbps_mbc"] > 0
        assert metrics["by_technology"]["GSM"]["freeze_ratio"] < 0.1
