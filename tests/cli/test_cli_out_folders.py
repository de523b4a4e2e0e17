"""Issue 28, items 1-2: uma removes only what it wrote, and a run folder and a sweep folder
never mix; every refusal is one line and exit 2, before any work."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from cli_folder import BASE, EXPERIMENT

from uma.cli import main

REPO = Path(__file__).resolve().parents[2]


def test_user_files_named_like_results_are_kept_and_the_run_refused(folder):
    out = folder / "R"
    (out / "timeline-notes.png").mkdir(parents=True)
    (out / "timeline-notes.png" / "mine.txt").write_text("mine")
    (out / ".precious.tmp").write_text("precious")
    done = subprocess.run(
        [sys.executable, "-m", "uma", "run", str(folder / "base.yaml"), "--out", str(out)],
        env=dict(os.environ, PYTHONPATH=str(REPO)),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("uma: error: --out: ")
    assert "holds files that are not results (.precious.tmp, timeline-notes.png)" in done.stderr
    assert (out / ".precious.tmp").read_text() == "precious"
    assert (out / "timeline-notes.png" / "mine.txt").read_text() == "mine"
    assert sorted(p.name for p in out.iterdir()) == [".precious.tmp", "timeline-notes.png"]


def test_a_link_named_like_a_result_is_not_uma_s(tmp_path):
    from uma.atomic import check_replaceable
    from uma.errors import OutputError
    from uma.metrics.results import RUN_FILES

    out = tmp_path / "R"
    out.mkdir()
    (tmp_path / "elsewhere.csv").write_text("mine")
    (out / "frames.csv").symlink_to(tmp_path / "elsewhere.csv")
    with pytest.raises(OutputError, match=r"not results \(frames.csv\)"):
        check_replaceable(out, RUN_FILES)


def test_uma_s_own_leftovers_are_replaceable(tmp_path):
    from uma.atomic import check_replaceable
    from uma.metrics.results import RUN_FILES

    out = tmp_path / "R"
    (out / ".R.uma-123@host-abc.tmp").mkdir(parents=True)
    (out / ".metrics.json.uma-99@host-x1y2.tmp").write_text("{")
    (out / "metrics.json").write_text("{}")
    check_replaceable(out, RUN_FILES)


def test_a_sweep_refuses_a_run_folder_and_a_run_refuses_a_sweep_folder(folder, capsys):
    # Refused before any work, so folders laid out as uma writes them will do.
    run = folder / "R"
    run.mkdir()
    for name in ("scenario.yaml", "metrics.json", "frames.csv", "events.csv"):
        (run / name).write_text("x")
    code = main(["sweep", str(folder / "exp.yaml"), "--out", str(run), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "holds files that are not results (events.csv, frames.csv, metrics.json, ...)" in err
    assert sorted(p.name for p in run.iterdir()) == [
        "events.csv",
        "frames.csv",
        "metrics.json",
        "scenario.yaml",
    ]

    sweep = folder / "S"
    (sweep / "points" / "0123456789abcdef").mkdir(parents=True)
    (sweep / "sweep.csv").write_text("x")
    (sweep / "sweep.parquet").write_text("x")
    code = main(["run", str(folder / "base.yaml"), "--out", str(sweep), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "holds files that are not results (points" in err, err
    assert sorted(p.name for p in sweep.iterdir()) == ["points", "sweep.csv", "sweep.parquet"]


def test_a_sweep_s_folder_takes_the_sweep_again(folder):
    from uma.experiments.sweep import check_sweep_out

    sweep = folder / "S"
    (sweep / "points").mkdir(parents=True)
    (sweep / "sweep.csv").write_text("x")
    (sweep / ".sweep.csv.uma-1@host-abc.tmp").write_text("x")
    assert check_sweep_out(sweep) == sweep


@pytest.mark.parametrize("command", ["run", "sweep", "regress"])
def test_an_empty_out_is_an_error(folder, capsys, monkeypatch, command):
    monkeypatch.chdir(folder)
    (folder / "suite.yaml").write_text(
        "baseline: b.yaml\nscenarios: [base.yaml]\n"
        "metrics:\n  freeze_ratio: {worse: up, absolute: 0.1}\n"
    )
    args = {
        "run": ["run", "base.yaml", "--quiet"],
        "sweep": ["sweep", "exp.yaml", "--quiet"],
        "regress": ["regress", "suite.yaml", "--update"],
    }[command]
    code = main([*args, "--out", ""])
    err = capsys.readouterr().err
    assert code == 2 and err == "uma: error: --out: expected a folder name, got ''\n"
    assert not (folder / "results").exists()


@pytest.mark.parametrize("which", ["image", "--points", "--model"])
def test_describe_refuses_a_fifo_a_device_or_a_loop_without_blocking(tmp_path, capsys, which):
    points = REPO / "codecs" / "face" / "akiyo.yaml"
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    for bad, said in (("fifo", "got a FIFO"), ("loop", "a symlink loop"), ("/dev/zero", "device")):
        path = bad if bad.startswith("/") else str(tmp_path / bad)
        argv = {
            "image": ["describe", path, "--points", str(points)],
            "--points": ["describe", "--points", path],
            "--model": ["describe", "--points", str(points), "--model", path],
        }[which]
        assert main([*argv, "--out", str(tmp_path / "out")]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and said in err, err


def test_names_and_paths_too_long_for_the_file_system_are_refused_before_running(folder, capsys):
    (folder / "long.yaml").write_text(BASE.replace("name: base", "name: " + "x" * 240))
    assert main(["run", str(folder / "long.yaml"), "--quiet"]) == 2
    assert "(name): string should have at most 100 characters" in capsys.readouterr().err
    out = str(folder / ("y" * 230))
    assert main(["run", str(folder / "base.yaml"), "--out", out, "--quiet"]) == 2
    assert "--out: expected a folder name of at most" in capsys.readouterr().err
    assert main(["sweep", str(folder / "exp.yaml"), "--out", "z" * 300, "--quiet"]) == 2
    assert "(names of at most 255 bytes)" in capsys.readouterr().err
    assert sorted(p.name for p in folder.iterdir()) == ["base.yaml", "exp.yaml", "long.yaml"]


@pytest.mark.parametrize("name", ["../../etc", "a/b", "x" * 101, ".hidden"])
def test_an_experiment_s_name_is_a_name_not_a_path(folder, capsys, name):
    (folder / "exp.yaml").write_text(EXPERIMENT.replace("name: grid", f"name: {name!r}"))
    assert main(["sweep", str(folder / "exp.yaml"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "exp.yaml:1 (name): expected a name of letters, digits" in err, err
