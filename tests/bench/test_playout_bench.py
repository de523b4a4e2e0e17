"""`uma bench playout`: settings replayed on recorded runs give the figures full runs give."""

import json

import pytest

from uma.bench.playout import (
    PlayoutBenchConfig,
    grid_settings,
    run_playout_bench,
    setting_receiver,
)
from uma.cli import main
from uma.config import load_scenario
from uma.sim import run_scenario
from uma.sim.summary import run_metrics

SETTING = {"rise_window_s": 0.5, "margin_ms": 100}


@pytest.fixture(scope="module")
def scenario_file(tmp_path_factory, playout_short_yaml):
    path = tmp_path_factory.mktemp("bench") / "s.yaml"
    path.write_text(playout_short_yaml)
    return path


@pytest.fixture(scope="module")
def bench(scenario_file):
    scenario = load_scenario(scenario_file)
    config = PlayoutBenchConfig(scenario=scenario, seeds=(2, 5), settings=(SETTING,))
    return scenario, run_playout_bench(config)


def test_the_own_playout_replays_exactly_and_has_no_change(bench):
    _, result = bench
    own = result["settings"][0]
    assert own["label"] == "own" and own["set"] == {}
    for seed, run in result["runs"].items():
        assert run["exact"] is True
        assert {key: own["seeds"][seed][key] for key in ("delay_p95_ms", "freeze_ratio")} == {
            key: run[key] for key in ("delay_p95_ms", "freeze_ratio")
        }
    assert own["change"]["delay_p95_ms"] == 0.0 and own["change"]["freeze_ratio"] == 0.0


def test_a_settings_figures_are_its_full_runs(bench):
    scenario, result = bench
    entry = result["settings"][1]
    assert entry["set"] == SETTING
    receiver = setting_receiver(scenario.receiver, SETTING)
    for seed in (2, 5):
        full = run_scenario(scenario.with_seed(seed).model_copy(update={"receiver": receiver}))
        metrics = run_metrics(full)
        row = entry["seeds"][str(seed)]
        for key in ("delay_p95_ms", "delay_median_ms", "freeze_ratio"):
            assert row[key] == metrics[key], (seed, key)
        assert row["by_technology"] == {
            tech: values["freeze_ratio"] for tech, values in metrics["by_technology"].items()
        }
    own = result["settings"][0]["seeds"]
    assert entry["seeds"] != own  # the setting moves the figures: the check can fail


def test_grid_settings_are_every_combination():
    grid = {"margin_ms": [20, 50], "window_s": 2.0}
    assert grid_settings(grid, {"rise_window_s": 0.5}) == [
        {"rise_window_s": 0.5, "margin_ms": 20, "window_s": 2.0},
        {"rise_window_s": 0.5, "margin_ms": 50, "window_s": 2.0},
    ]


def test_cli_json(scenario_file, tmp_path, capsys):
    grid = tmp_path / "grid.yaml"
    grid.write_text("margin_ms: [50, 100]\n")
    code = main(
        ["bench", "playout", "--scenario", str(scenario_file), "--seeds", "2",
         "--grid", str(grid), "--set", "rise_window_s=0.5", "--json"]
    )  # fmt: skip
    assert code == 0
    result = json.loads(capsys.readouterr().out)
    labels = [entry["label"] for entry in result["settings"]]
    assert labels == ["own", "rise_window_s=0.5 margin_ms=50", "rise_window_s=0.5 margin_ms=100"]
    assert result["runs"]["2"]["exact"] is True


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--set", "foo=1"], "--set: foo: unknown receiver.adaptive key"),
        (["--set", "margin_ms=abc"], "--set: margin_ms:"),
        (["--set", "margin_ms"], "expected KEY=VALUE"),
        (["--set", "margin_ms=[a"], "--set margin_ms:1: invalid YAML"),
        (["--set", "percentile=200"], "percentile"),
        (["--seeds", "1,x"], "--seeds"),
        (["--seeds", "1,1"], "--seeds"),
        (["--grid", "MISSING"], "no such grid file"),
        (["--grid", "NOTGRID"], "--grid"),
        (["--grid", "BADYAML"], "not YAML"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(scenario_file, tmp_path, capsys, arguments, message):
    (tmp_path / "notgrid.yaml").write_text("- 1\n- 2\n")
    (tmp_path / "bad.yaml").write_text("x: [\n")
    names = {
        "MISSING": tmp_path / "missing.yaml",
        "NOTGRID": tmp_path / "notgrid.yaml",
        "BADYAML": tmp_path / "bad.yaml",
    }
    arguments = [str(names.get(a, a)) for a in arguments]
    assert main(["bench", "playout", "--scenario", str(scenario_file), *arguments]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
