"""Issue 28, items 10-11: a suite whose metric path no scenario has, or whose `only:` names
no scenario of the suite, is refused in one line (exit 2), at --update too, so no gate
silently checks nothing. Results are read with --results: no simulation runs here."""

import json

import pytest

from uma.cli import main

SCENARIO = "name: {name}\nroute:\n  - {{technology: GSM, duration_s: 1}}\n"
METRICS = {
    "freeze_ratio": 0.5,
    "psnr_db": 30.0,
    "by_technology": {"GSM": {"freeze_ratio": 0.9, "psnr_face_db": None}},
}


@pytest.fixture
def folder(tmp_path):
    for name in ("switching-gsm", "cell-edge"):
        (tmp_path / f"{name}.yaml").write_text(SCENARIO.format(name=name))
        (tmp_path / "results" / name).mkdir(parents=True)
        (tmp_path / "results" / name / "metrics.json").write_text(json.dumps(METRICS))
    return tmp_path


def regress(folder, capsys, metrics: str, *, update: bool):
    (folder / "suite.yaml").write_text(
        "baseline: baseline.yaml\nscenarios: [switching-gsm.yaml, cell-edge.yaml]\nmetrics:\n"
        + metrics
    )
    argv = ["regress", str(folder / "suite.yaml"), "--results", str(folder / "results")]
    code = main(argv + (["--update"] if update else []))
    return code, capsys.readouterr()


@pytest.mark.parametrize("update", [True, False])
def test_a_metric_path_no_scenario_has_is_an_error(folder, capsys, update):
    if not update:  # a baseline written before the typo
        assert (
            regress(folder, capsys, "  freeze_ratio: {worse: up, absolute: 0.1}\n", update=True)[0]
            == 0
        )
        text = (folder / "baseline.yaml").read_text()
        (folder / "baseline.yaml").write_text(
            text.replace(
                "freeze_ratio: 0.5", "freeze_ratio: 0.5\n  by_technology.GMS.freeze_ratio: null"
            )
        )
    code, out = regress(
        folder,
        capsys,
        "  freeze_ratio: {worse: up, absolute: 0.1}\n"
        "  by_technology.GMS.freeze_ratio: {worse: up, absolute: 0.02}\n",
        update=update,
    )
    assert code == 2 and out.err.count("\n") == 1, out.err
    assert out.err == (
        f"uma: error: {folder / 'suite.yaml'}:5 (metrics.by_technology.GMS.freeze_ratio): no "
        f"scenario's metrics.json has 'by_technology.GMS.freeze_ratio' (looked in "
        f"switching-gsm, cell-edge); did you mean 'by_technology.GSM.freeze_ratio'?\n"
    )


def test_a_null_metric_is_a_metric_and_a_lacking_scenario_is_refused_at_update(folder, capsys):
    code, out = regress(
        folder,
        capsys,
        "  by_technology.GSM.psnr_face_db: {worse: down, absolute: 0.3}\n",
        update=True,
    )
    assert code == 0, out.err
    metrics = dict(METRICS)
    del metrics["psnr_db"]
    (folder / "results" / "cell-edge" / "metrics.json").write_text(json.dumps(metrics))
    code, out = regress(folder, capsys, "  psnr_db: {worse: down, absolute: 0.3}\n", update=True)
    assert code == 2
    assert "cell-edge's metrics.json has no 'psnr_db'; gate it with only:" in out.err
    code, out = regress(
        folder,
        capsys,
        "  psnr_db: {worse: down, absolute: 0.3, only: [switching-gsm]}\n",
        update=True,
    )
    assert code == 0, out.err


@pytest.mark.parametrize("only", ["gsm", "switching-gsm.yaml"])
def test_only_must_name_a_scenario_of_the_suite(folder, capsys, only):
    code, out = regress(
        folder,
        capsys,
        f"  freeze_ratio: {{worse: up, absolute: 0.1, only: [{only}]}}\n",
        update=True,
    )
    assert code == 2 and out.err.count("\n") == 1
    assert (
        "suite.yaml:4 (metrics.freeze_ratio) only: expected scenario names of this suite "
        "(switching-gsm, cell-edge)" in out.err
    )
    assert f"got {only!r}" in out.err
    assert ("not its file" in out.err) == only.endswith(".yaml")
    assert not (folder / "baseline.yaml").exists()


@pytest.mark.parametrize(
    "make, said",
    [
        ("fifo", "expected a metrics.json of a finished run (a regular file), got a FIFO"),
        ("deep", "got JSON nested too deeply"),
        ("inf", "(freeze_ratio): expected a finite number or null for the baseline, got inf"),
    ],
)
def test_hostile_results_are_one_line_and_no_baseline(folder, capsys, make, said):
    import os

    path = folder / "results" / "cell-edge" / "metrics.json"
    path.unlink()
    if make == "fifo":
        os.mkfifo(path)
    elif make == "deep":
        path.write_text('{"a":' * 100_000 + "1" + "}" * 100_000)
    else:
        path.write_text('{"freeze_ratio": 1e999}')
    code, out = regress(folder, capsys, "  freeze_ratio: {worse: up, absolute: 0.1}\n", update=True)
    assert code == 2 and out.err.count("\n") == 1 and said in out.err, out.err
    assert not (folder / "baseline.yaml").exists()
