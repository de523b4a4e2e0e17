import json
import math

import numpy as np
import pytest

from uma.metrics.aggregate import aggregate, ssim_to_db
from uma.metrics.delay import display_delays_ms
from uma.metrics.framelog import COLUMNS, FrameLog
from uma.metrics.results import write_results


def test_every_frame_on_time_has_the_playout_delay():
    capture = np.arange(5) * 40.0
    display = capture + 300.0
    shown = np.arange(5)
    assert display_delays_ms(capture, display, shown).tolist() == [300.0] * 5


def test_undisplayed_frame_counts_with_the_next_displayed():
    capture = np.arange(5) * 40.0
    display = capture + 300.0
    shown = np.array([0, 0, 0, 3, 4])  # frames 1 and 2 never shown; 3 shown at its slot
    delays = display_delays_ms(capture, display, shown)
    assert delays.tolist() == [300.0, 380.0, 340.0, 300.0, 300.0]


def test_late_frame_counts_from_its_first_display():
    capture = np.arange(4) * 40.0
    display = capture + 300.0
    shown = np.array([0, 0, 1, 3])  # frame 1 arrived late, first shown at slot 2
    delays = display_delays_ms(capture, display, shown)
    assert delays.tolist() == [300.0, 340.0, 340.0, 300.0]


def test_frames_after_last_display_use_last_instant():
    capture = np.arange(3) * 40.0
    display = capture + 300.0
    shown = np.array([-1, 0, 0])
    delays = display_delays_ms(capture, display, shown)
    assert delays[0] == pytest.approx(340.0)
    assert delays[2] == pytest.approx(380.0 - 80.0)


def test_ssim_db():
    assert ssim_to_db(0.9) == pytest.approx(10.0)
    assert ssim_to_db(1.0) == 100.0
    assert math.isnan(ssim_to_db(float("nan")))


def test_aggregate_counts():
    log = FrameLog(4)
    log["capture_ms"][:] = np.arange(4) * 40.0
    log["display_ms"][:] = log["capture_ms"] + 300.0
    log["shown_frame"][:] = [0, 0, 2, 3]
    log["frozen"][:] = [0, 1, 0, 0]
    log["codec"][:] = ["h264", "h264", "h264", ""]
    log["size_bits"][:] = [8000, 4000, 4000, 0]
    log["psnr_db"][:] = [40.0, 30.0, 40.0, 30.0]
    log["ssim"][:] = [0.9, 0.9, 0.9, 0.9]
    link = {"bits_delivered": 16000, "packets_sent": 4}
    out = aggregate(
        log,
        duration_s=0.16,
        capacity_bits=32000,
        link=link,
        event_kinds=["rung_switch", "handover", "rung_switch"],
    )
    assert out["bits_sent"] == {"h264": 16000, "h264-face": 0, "mbc": 0}
    assert out["kbps_h264"] == pytest.approx(100.0)
    assert out["link_utilisation"] == 0.5
    assert out["freeze_ratio"] == 0.25
    assert out["psnr_db"] == 35.0
    assert out["ssim_db"] == pytest.approx(10.0)
    assert out["switches"] == 2 and out["handovers"] == 1
    json.dumps(out)  # serialisable


def test_frame_csv_header_and_rows():
    log = FrameLog(2)
    text = log.to_csv()
    lines = text.splitlines()
    assert lines[0].split(",") == list(COLUMNS)
    assert len(lines) == 3


def test_write_results_writes_all_files(tmp_path):
    out = write_results(
        tmp_path / "r",
        scenario_yaml="name: x\n",
        metrics={"a": 1},
        frames_csv="frame\n",
        events_csv_text="time_ms,kind,detail\n",
    )
    assert sorted(p.name for p in out.iterdir()) == [
        "events.csv",
        "frames.csv",
        "metrics.json",
        "scenario.yaml",
    ]
    assert json.loads((out / "metrics.json").read_text()) == {"a": 1}


def test_ssim_db_comes_from_the_unrounded_mean():
    # mean SSIM 0.99996: rounded to 4 decimals it would read 1.0 and 100 dB
    log = FrameLog(2)
    log["capture_ms"][:] = [0.0, 40.0]
    log["display_ms"][:] = [300.0, 340.0]
    log["shown_frame"][:] = [0, 1]
    log["ssim"][:] = [0.99995, 0.99997]
    out = aggregate(
        log, duration_s=0.08, capacity_bits=1000, link={"bits_delivered": 0}, event_kinds=[]
    )
    assert out["ssim"] == 1.0
    assert out["ssim_db"] == pytest.approx(-10 * math.log10(1 - 0.99996), abs=1e-4)
