"""Fault injection from YAML: each run completes, accounts for every frame and packet, and
writes complete results."""

import json

import numpy as np
import pytest

from uma.config import load_scenario
from uma.config.scenario import FaultsConfig, LossBurstConfig
from uma.sim import run_scenario
from uma.sim.faults import Faults
from uma.sim.summary import save_run

BASE = """\
name: faulty
seed: 3
source: {kind: pattern, width: 96, height: 64, fps: 25}
route:
  - {technology: 3G, duration_s: 4}
  - {technology: GPRS, duration_s: 2}
metrics: {workers: 0}
"""
FRAMES = 150


def run(tmp_path, faults_yaml=""):
    path = tmp_path / "s.yaml"
    path.write_text(BASE + faults_yaml)
    result = run_scenario(load_scenario(path))
    metrics = save_run(result, tmp_path / "out")
    return result, metrics


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    return run(tmp_path_factory.mktemp("clean"))


def check_complete(tmp_path, result, metrics, clean_metrics):
    out = tmp_path / "out"
    assert sorted(p.name for p in out.iterdir()) == [
        "events.csv", "frames.csv", "metrics.json", "scenario.yaml"
    ]  # fmt: skip
    assert set(json.loads((out / "metrics.json").read_text())) == set(clean_metrics)
    rows = (out / "frames.csv").read_text().splitlines()
    assert len(rows) == FRAMES + 1 and metrics["frames"] == FRAMES
    log = result.log
    assert np.all(np.isfinite(log["display_ms"])) and set(np.unique(log["frozen"])) <= {0, 1}
    # every frame is shown, or frozen over an earlier one (or nothing yet)
    assert np.all(log["shown_frame"] <= log["frame"])
    p = metrics["packets"]
    assert p["packets_sent"] == (
        p["packets_dropped_queue"] + p["packets_lost_random"] + p["packets_lost_burst"]
        + p["packets_delivered"] + p["packets_queued_at_end"]
    )  # fmt: skip


def test_no_faults_is_the_run_as_before(clean):
    result, metrics = clean
    p = metrics["packets"]
    assert p["packets_lost_burst"] == p["packets_reordered"] == 0


def test_gilbert_elliott_bursts_have_the_chains_length_and_rate():
    config = FaultsConfig(
        loss_bursts=LossBurstConfig(p_good_to_bad=0.05, p_bad_to_good=0.2, loss_bad=1.0)
    )
    faults = Faults(config, rng=np.random.default_rng(7))
    lost = np.array([faults.burst_lost() for _ in range(40000)])
    assert lost.mean() == pytest.approx(0.05 / 0.25, abs=0.02)  # stationary share of bad
    edges = np.flatnonzero(np.diff(np.concatenate([[0], lost.astype(int), [0]])))
    runs = edges[1::2] - edges[::2]
    assert runs.mean() == pytest.approx(1 / 0.2, rel=0.1)  # mean burst of 1 / p_bad_to_good


def test_loss_bursts(tmp_path, clean):
    faults = "faults:\n  loss_bursts: {p_good_to_bad: 0.05, p_bad_to_good: 0.3, loss_bad: 0.8}\n"
    result, metrics = run(tmp_path, faults)
    check_complete(tmp_path, result, metrics, clean[1])
    assert metrics["packets"]["packets_lost_burst"] > 5
    assert metrics["keyframe_requests"] > clean[1]["keyframe_requests"]
    assert metrics["freeze_ratio"] > clean[1]["freeze_ratio"]


def test_outage_longer_than_the_run(tmp_path, clean):
    result, metrics = run(tmp_path, "faults:\n  outages: [{start_s: 1.5, duration_s: 1000}]\n")
    check_complete(tmp_path, result, metrics, clean[1])
    p = metrics["packets"]
    assert p["packets_queued_at_end"] + p["packets_dropped_queue"] > 0
    log = result.log
    late = log["capture_ms"] > 1500 + 400  # captured after the outage began, beyond the playout
    assert log["frozen"][late].all() and not log["decoded"][late].any()
    assert metrics["capacity_mean_kbps"] < clean[1]["capacity_mean_kbps"]


def test_reordering(tmp_path, clean):
    result, metrics = run(tmp_path, "faults:\n  reorder: {probability: 0.1, delay_ms: 60}\n")
    check_complete(tmp_path, result, metrics, clean[1])
    assert metrics["packets"]["packets_reordered"] > 5
    assert metrics["frames_decoded"] < clean[1]["frames_decoded"]


def test_silent_feedback_channel(tmp_path, clean):
    faults = "faults:\n  feedback_silence: [{start_s: 1.0, duration_s: 2.0}]\n"
    result, metrics = run(tmp_path, faults)
    check_complete(tmp_path, result, metrics, clean[1])
    assert metrics["feedback_lost"] >= clean[1]["feedback_lost"] + 19  # 20 reports at 100 ms
    log = result.log
    before = log["estimate_kbps"][(log["capture_ms"] > 800) & (log["capture_ms"] < 1000)]
    during = log["estimate_kbps"][(log["capture_ms"] > 2800) & (log["capture_ms"] < 3000)]
    assert np.nanmax(during) < 0.2 * np.nanmin(before)  # the stale-report decrease, every 100 ms


def test_bad_fault_keys_name_the_line(tmp_path):
    from uma.errors import ConfigError

    path = tmp_path / "s.yaml"
    path.write_text(BASE + "faults:\n  outages: [{start_s: 1}]\n")
    with pytest.raises(ConfigError, match=r"s.yaml:9 \(faults.outages\[0\].duration_s\): missing"):
        load_scenario(path)
    path.write_text(BASE + "faults:\n  loss_bursts: {p_good_to_bad: 2}\n")
    with pytest.raises(ConfigError, match=r"faults.loss_bursts.p_good_to_bad"):
        load_scenario(path)
