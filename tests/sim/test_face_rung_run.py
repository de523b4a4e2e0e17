"""Whole runs with the face-region rungs: WLAN, GSM, WLAN; no face; bad configuration."""

import numpy as np
import pytest

from uma.cli import main
from uma.config import load_scenario
from uma.config.scenario import Scenario
from uma.errors import ConfigError
from uma.sim import run_scenario
from uma.sim.summary import run_metrics

ROUTE = [
    {"technology": "WLAN", "duration_s": 2.0},
    {"technology": "GSM", "duration_s": 5.0},
    {"technology": "WLAN", "duration_s": 4.0},
]


def scenario(source="talking-head", **face):
    return Scenario.model_validate(
        {
            "name": "face-rung",
            "seed": 1,
            "source": {"kind": source, "width": 176, "height": 144, "fps": 25},
            "route": ROUTE,
            "engine": {"policy": "oracle", "face_region": {"enabled": True} | face},
            "receiver": {"playout_delay_ms": 800.0},
            "metrics": {"ssim": False, "workers": 0},
        }
    )


@pytest.fixture(scope="module")
def run():
    return run_scenario(scenario())


def test_gsm_goes_onto_the_face_rung_and_back(run):
    log = run.log
    codec = np.array([str(c) for c in log["codec"]])
    tech = np.array([str(t) for t in log["technology"]])
    face = codec == "h264-face"
    assert (face & (tech == "GSM")).sum() >= 12  # of 25 scheduled
    # In WLAN only while the oracle climbs back (one rung a second after the handover gap).
    t_s = np.arange(log.frames) / 25.0
    assert np.all((t_s[face & (tech == "WLAN")] >= 7.0) & (t_s[face & (tech == "WLAN")] < 10.0))
    # Rungs of one rate ladder: rung switches, not codec switches (those are to and from MBC).
    assert "codec_switch" not in [e.kind for e in run.events]
    moves = [e.detail.split()[0] for e in run.events if e.kind == "rung_switch"]
    faces = {str(i) for i, p in enumerate(run.points) if p.codec == "h264-face"}
    into = [m for m in moves if m.split("->")[1] in faces and m.split("->")[0] not in faces]
    back = [m for m in moves if m.split("->")[0] in faces and m.split("->")[1] not in faces]
    assert len(into) == 1 and len(back) == 1
    # GSM's 9.6 kbit/s x 0.85 carries the 8 kbit/s face rung, not the 16 kbit/s full frame.
    rungs = {run.points[int(r)].label for r in log["rung"][face & (tech == "GSM")]}
    assert rungs == {"h264-face 8k 48x48@5"}
    # Back in WLAN the oracle climbs through the 12 kbit/s face rung to the full frame.
    climb = {run.points[int(r)].label for r in log["rung"][face & (tech == "WLAN")]}
    assert climb <= {"h264-face 8k 48x48@5", "h264-face 12k 48x48@5"}


def test_every_frame_is_accounted_for(run):
    log = run.log
    n = log.frames
    assert n == 11 * 25
    sent = log["sent"].astype(bool)
    decoded = log["decoded"].astype(bool)
    codec = np.array([str(c) for c in log["codec"]])
    assert np.all(log["scheduled"].astype(bool)[sent])
    assert set(codec[sent]) == {"h264", "h264-face"} and set(codec[~sent]) <= {""}
    assert np.all(sent[decoded])
    shown = log["shown_frame"].astype(int)
    assert np.all(shown <= np.arange(n))
    assert np.all((shown == -1) | decoded[np.clip(shown, 0, None)])
    shown_codec = np.array([str(c) for c in log["shown_codec"]])
    assert np.array_equal(shown_codec[shown >= 0], codec[shown[shown >= 0]])
    assert "h264-face" in set(shown_codec)
    face = codec == "h264-face"
    assert decoded[face].mean() > 0.8  # the rung fits GSM
    # The face rung's bits are its own, header included, and on the wire at about its rate.
    metrics = run_metrics(run)
    face_bits = int(log["size_bits"][face].sum())
    assert metrics["bits_sent"]["h264-face"] == face_bits > 0
    assert metrics["kbps_h264_face"] == round(face_bits / run.duration_s / 1000.0, 3)
    assert metrics["bits_sent"]["h264"] == int(log["size_bits"][codec == "h264"].sum())
    assert 3.0 < face_bits / 1000.0 / 5.0 < 8.5  # kbit/s over the GSM stretch


def test_face_rung_freezes_less_than_h264_alone_in_gsm(run):
    alone = run_scenario(scenario(enabled=False))
    tech = np.array([str(t) for t in run.log["technology"]])
    gsm = tech == "GSM"
    assert run.log["frozen"][gsm].mean() < alone.log["frozen"][gsm].mean()


def test_no_face_falls_back_to_the_lowest_full_frame_rung_and_completes():
    result = run_scenario(scenario(source="pattern", retry_ms=2000.0))
    log = result.log
    codec = np.array([str(c) for c in log["codec"]])
    assert "h264-face" not in set(codec)  # never a face-region frame sent
    failed = [e for e in result.events if e.kind == "face_region_failed"]
    assert failed and "no face detected" in failed[0].detail
    assert 1 <= len(failed) <= 3  # retried after retry_ms, not every frame
    assert result.engine_counts["face_region_failures"] == len(failed)
    tech = np.array([str(t) for t in log["technology"]])
    gsm_rungs = {result.points[int(r)].label for r in log["rung"][(tech == "GSM") & (codec != "")]}
    assert gsm_rungs == {"h264 16k 128x96@5"}
    assert log["sent"][tech == "GSM"].sum() > 0
    assert np.isfinite(log["display_ms"]).all()


def test_bad_face_region_keys_are_refused(tmp_path):
    base = "name: x\nroute: [{technology: WLAN, duration_s: 1}]\nengine:\n  face_region:\n"
    cases = {
        "    rungs: [{rate_kbps: 12, width: 64, height: 64, fps: 5}, "
        "{rate_kbps: 8, width: 64, height: 64, fps: 5}]\n": "strictly increasing",
        "    rungs: [{rate_kbps: 8, width: 63, height: 64, fps: 5}]\n": "even",
        "    margin: 2\n": "margin",
        "    detect_every_frames: 0\n": "detect_every_frames",
        "    enabled: yes please\n": "enabled",
    }
    for text, expected in cases.items():
        path = tmp_path / "s.yaml"
        path.write_text(base + text)
        with pytest.raises(ConfigError, match=expected):
            load_scenario(path)


def test_face_rung_at_or_above_the_full_frame_ladder_is_exit_2(tmp_path, capsys):
    path = tmp_path / "s.yaml"
    path.write_text(
        "name: x\nroute: [{technology: WLAN, duration_s: 1}]\nengine:\n  face_region:\n"
        "    enabled: true\n    rungs: [{rate_kbps: 16, width: 64, height: 64, fps: 5}]\n"
    )
    assert main(["run", str(path), "--out", str(tmp_path / "r"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "engine.face_region.rungs[0].rate_kbps" in err[0]
    assert not (tmp_path / "r" / "metrics.json").exists()
