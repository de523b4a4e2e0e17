"""`uma regress`: passes on the committed baseline (tiny_baseline.yaml), fails on a deliberately
worse one, and on a missing metric; bad suite or baseline files are exit 2 naming the line."""

import json
import re
import shutil
from pathlib import Path

import pytest

from uma.cli import main

SCENARIO = """\
name: tiny
seed: 1
source: {kind: pattern, width: 96, height: 64, fps: 25}
route:
  - {technology: 3G, duration_s: 1.5}
  - {technology: GPRS, duration_s: 1.5}
"""
SUITE = """\
baseline: baseline.yaml
scenarios: [tiny.yaml]
metrics:
  kbps_h264: {worse: up, relative: 0.05}
  psnr_db: {worse: down, absolute: 0.3}
  freeze_ratio: {worse: up, absolute: 0.02}
"""


# Committed, not written by this run: the fixture's first run is checked against it, so the
# module fails when the behaviour moves beyond the suite's tolerances (a regression).
COMMITTED_BASELINE = Path(__file__).with_name("tiny_baseline.yaml")


@pytest.fixture(scope="module")
def suite(tmp_path_factory):
    folder = tmp_path_factory.mktemp("suite")
    (folder / "tiny.yaml").write_text(SCENARIO)
    (folder / "suite.yaml").write_text(SUITE)
    shutil.copyfile(COMMITTED_BASELINE, folder / "baseline.yaml")
    code = main(["regress", str(folder / "suite.yaml"), "--out", str(folder / "runs")])
    assert code == 0, f"today's run regressed against {COMMITTED_BASELINE.name} (table above)"
    return folder


def baseline_with(suite, **changes):
    import yaml

    data = yaml.safe_load((suite / "baseline.yaml").read_text())
    data["tiny"] |= changes
    return data


def test_true_baseline_passes_and_prints_one_row_a_check(suite, capsys):
    # The fixture's new run passed against the committed baseline; its stored results are read
    # back here (a second run would only repeat it) to check the table.
    capsys.readouterr()
    assert main(["regress", str(suite / "suite.yaml"), "--results", str(suite / "runs")]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0].split() == [
        "scenario",
        "metric",
        "baseline",
        "now",
        "change",
        "tolerance",
        "verdict",
    ]
    assert "REGRESSED" not in out and "3 checks, 0 regressed" in out


def test_worse_baseline_fails_and_names_the_metric(suite, capsys, tmp_path):
    import yaml

    data = baseline_with(suite)
    # A baseline 1 dB better than today: today's PSNR has "fallen" past the 0.3 dB tolerance.
    data["tiny"]["psnr_db"] += 1.0
    data["tiny"]["kbps_h264"] *= 0.9  # and today's rate "rose" 11 %
    folder = tmp_path / "worse"
    folder.mkdir()
    (folder / "tiny.yaml").write_text(SCENARIO)
    (folder / "suite.yaml").write_text(SUITE)
    (folder / "baseline.yaml").write_text(yaml.safe_dump(data))
    capsys.readouterr()
    assert main(["regress", str(folder / "suite.yaml"), "--results", str(suite / "runs")]) == 1
    lines = capsys.readouterr().out.splitlines()
    verdicts = {line.split()[1]: line.split()[-1] for line in lines[1:-1]}
    assert verdicts == {"kbps_h264": "REGRESSED", "psnr_db": "REGRESSED", "freeze_ratio": "ok"}


def test_missing_metric_is_a_regression(suite, capsys, tmp_path):
    results = tmp_path / "tiny"
    results.mkdir()
    metrics = json.loads((suite / "runs" / "tiny" / "metrics.json").read_text())
    del metrics["psnr_db"]
    (results / "metrics.json").write_text(json.dumps(metrics))
    assert main(["regress", str(suite / "suite.yaml"), "--results", str(tmp_path)]) == 1
    assert "missing" in capsys.readouterr().out


def test_update_says_what_changed(suite, capsys, tmp_path):
    folder = tmp_path / "s"
    shutil.copytree(suite, folder, ignore=shutil.ignore_patterns("runs"))
    text = (folder / "baseline.yaml").read_text().replace("psnr_db: ", "psnr_db: 1")
    (folder / "baseline.yaml").write_text(text)
    capsys.readouterr()
    assert (
        main(["regress", str(folder / "suite.yaml"), "--update", "--results", str(suite / "runs")])
        == 0
    )
    out = capsys.readouterr().out
    assert "REGRESSED" in out and "baseline" in out.splitlines()[-1]
    import yaml

    rewritten = yaml.safe_load((folder / "baseline.yaml").read_text())
    assert rewritten == yaml.safe_load(COMMITTED_BASELINE.read_text())


@pytest.mark.parametrize(
    "baseline, message",
    [
        ("tiny:\n  kbps_h264: 12\n  psnr_db: 30: 1\n", r"baseline.yaml:3: invalid YAML"),
        (
            "tiny:\n  kbps_h264: 12 kbit/s\n",
            r"baseline.yaml:2 \(tiny.kbps_h264\): expected a number or null",
        ),
        ("other:\n  kbps_h264: 1\n", r"no baseline for scenario 'tiny'"),
    ],
)
def test_malformed_baseline_is_exit_2_naming_the_line(suite, capsys, tmp_path, baseline, message):
    (tmp_path / "tiny.yaml").write_text(SCENARIO)
    (tmp_path / "suite.yaml").write_text(SUITE)
    (tmp_path / "baseline.yaml").write_text(baseline)
    assert main(["regress", str(tmp_path / "suite.yaml"), "--results", str(suite / "runs")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert re.search(message, err[0]), err[0]


def test_bad_suite_names_the_key(tmp_path, capsys):
    (tmp_path / "suite.yaml").write_text(
        SUITE.replace("worse: up, relative", "worse: sideways, relative")
    )
    assert main(["regress", str(tmp_path / "suite.yaml")]) == 2
    assert "suite.yaml:4 (metrics.kbps_h264) worse: expected up or down" in capsys.readouterr().err


@pytest.mark.parametrize(
    "damage, said",
    [
        (
            lambda text: text[: len(text) // 2],
            r"metrics.json:\d+: expected the JSON metrics .* got truncated JSON",
        ),
        (lambda text: '{\n  "psnr_db": 3,, \n}\n', r"metrics.json:2: .*got unparseable JSON"),
        (lambda text: "[1, 2]\n", r"metrics.json:1: expected a JSON object of metrics, got list"),
    ],
)
def test_truncated_metrics_file_is_named_as_such_not_missing(suite, capsys, tmp_path, damage, said):
    results = tmp_path / "tiny"
    results.mkdir()
    text = (suite / "runs" / "tiny" / "metrics.json").read_text()
    (results / "metrics.json").write_text(damage(text))
    capsys.readouterr()
    assert main(["regress", str(suite / "suite.yaml"), "--results", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "no " not in err, err
    assert re.search(said, err), err


def test_regress_refuses_an_out_folder_holding_other_files_before_running(suite, capsys, tmp_path):
    (tmp_path / "tiny").mkdir()
    (tmp_path / "tiny" / "notes.txt").write_text("mine")
    capsys.readouterr()
    assert main(["regress", str(suite / "suite.yaml"), "--out", str(tmp_path)]) == 2
    assert "holds files that are not results (notes.txt)" in capsys.readouterr().err
    assert (tmp_path / "tiny" / "notes.txt").read_text() == "mine"


def test_dotted_metrics_and_only_gate_the_scenarios_they_name(tmp_path):
    from uma.experiments.regress import compare, load_suite, metric_value

    (tmp_path / "suite.yaml").write_text(
        "baseline: b.yaml\nscenarios: [a.yaml]\nmetrics:\n"
        "  psnr_db: {worse: down, absolute: 0.3}\n"
        "  by_technology.GSM.freeze_ratio: {worse: up, absolute: 0.02, only: [sw]}\n"
    )
    suite = load_suite(tmp_path / "suite.yaml")
    assert set(suite.metrics_of("plain")) == {"psnr_db"}
    assert set(suite.metrics_of("sw")) == {"psnr_db", "by_technology.GSM.freeze_ratio"}
    now = {
        "plain": {"psnr_db": 30.0},
        "sw": {"psnr_db": 30.0, "by_technology": {"GSM": {"freeze_ratio": 0.2}}},
    }
    assert metric_value(now["sw"], "by_technology.GSM.freeze_ratio") == 0.2
    assert metric_value(now["sw"], "by_technology.GPRS.freeze_ratio") is None
    baseline = {
        "plain": {"psnr_db": 30.0},
        "sw": {"psnr_db": 30.0, "by_technology.GSM.freeze_ratio": 0.1},
    }
    verdicts = {(c.scenario, c.metric): c.verdict for c in compare(suite, baseline, now)}
    assert verdicts == {
        ("plain", "psnr_db"): "ok",
        ("sw", "psnr_db"): "ok",
        ("sw", "by_technology.GSM.freeze_ratio"): "REGRESSED",
    }


def test_only_must_name_scenarios(tmp_path, capsys):
    (tmp_path / "suite.yaml").write_text(
        "baseline: b.yaml\nscenarios: [a.yaml]\nmetrics:\n"
        "  psnr_db: {worse: down, absolute: 0.3, only: sw}\n"
    )
    assert main(["regress", str(tmp_path / "suite.yaml")]) == 2
    assert "suite.yaml:4" in capsys.readouterr().err
