"""`uma bench bound`: no run's frame beats its link's bound; JSON keys; bad input as exit 2."""

from __future__ import annotations

import json

import numpy as np
import pytest

from uma.bench.bound import BoundConfig, scenario_bound
from uma.cli import main
from uma.config import load_scenario
from uma.metrics.link_bound import frame_delay_bounds_s
from uma.sim import run_scenario
from uma.sim.summary import run_metrics
from uma.sim.world import scenario_link

SCENARIO = """\
name: bounded
seed: 5
source: {kind: pattern, width: 96, height: 64, fps: 25}
route:
  - {technology: 3G, duration_s: 3}
  - {technology: GPRS, duration_s: 2}
  - {technology: GSM, duration_s: 2}
metrics: {workers: 0}
faults:
  outages: [{start_s: 1.0, duration_s: 1.2}]
"""


@pytest.fixture(scope="module")
def scenario_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("bound") / "bounded.yaml"
    path.write_text(SCENARIO, encoding="utf-8")
    return path


def test_no_frame_of_a_run_is_shown_sooner_than_its_link_allows(scenario_file):
    scenario = load_scenario(scenario_file)
    result = run_scenario(scenario)
    run_metrics(result)  # fills the log's delay_ms
    capacity, delay_s_of = scenario_link(scenario)
    assert np.array_equal(capacity.rates_bps, result.capacity.rates_bps)
    log = result.log
    delay_ms = np.asarray(log["delay_ms"])
    bound_ms = 1000.0 * frame_delay_bounds_s(
        capacity, delay_s_of, np.asarray(log["capture_ms"]) / 1000.0, size_bits=320
    )
    shown = np.isfinite(delay_ms)
    assert shown.sum() > 100
    assert np.all(delay_ms[shown] >= bound_ms[shown])
    # The outage binds: frames captured in it are bound by the wait for the link's return.
    in_outage = (log["capture_ms"] >= 1100) & (log["capture_ms"] < 2000)
    assert np.all(bound_ms[in_outage] >= 200.0)


def test_the_bench_counts_the_runs_frames(scenario_file):
    scenario = load_scenario(scenario_file)
    row = scenario_bound(scenario, BoundConfig(scenarios=(scenario,), packet_bytes=(40, 1200)))
    assert row["frames"] == 175 and row["fps"] == 25.0 and row["seed"] == 5
    small, large = row["packets"]["40"], row["packets"]["1200"]
    assert 0 < small["delay_p95_ms"] <= large["delay_p95_ms"]


def test_bound_json_has_the_documented_keys(scenario_file, capsys):
    argv = ["bench", "bound", "--scenario", str(scenario_file), "--json", "--seed", "2"]
    assert main(argv) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["packet_bytes"] == [40, 120, 1200]
    row = result["scenarios"]["bounded"]
    assert set(row) == {"seed", "fps", "frames", "duration_s", "packets"} and row["seed"] == 2
    for summary in row["packets"].values():
        assert set(summary) == {"delay_p95_ms", "delay_median_ms", "share_over_s"}
        assert set(summary["share_over_s"]) == {"1", "1.5"}


@pytest.mark.parametrize(
    "args, expected",
    [
        (["--packet-bytes", "40,x"], "--packet-bytes"),
        (["--packet-bytes", "0"], "--packet-bytes"),
        (["--scenario", "/no/such/scenario.yaml"], "--scenario"),
    ],
)
def test_bound_bad_input_is_one_line_and_exit_2(args, expected, scenario_file, capsys):
    full = ["bench", "bound", *args]
    if "--scenario" not in args:
        full += ["--scenario", str(scenario_file)]
    assert main(full) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and expected in err[0]
