"""`uma run --set KEY=VALUE`: a scenario key's value for one run, checked as the file's own."""

import pytest
import yaml

from uma.cli import main


def test_set_values_reach_the_run_and_its_scenario_file(folder):
    out = folder / "out"
    argv = ["run", str(folder / "base.yaml"), "--out", str(out), "--quiet"]
    sets = ["--set", "engine.policy=oracle", "--set", "seed=7", "--set", "source.fps=10"]
    assert main(argv + sets) == 0
    written = yaml.safe_load((out / "scenario.yaml").read_text())
    assert written["engine"]["policy"] == "oracle"
    assert written["seed"] == 7
    assert written["source"]["fps"] == 10
    assert yaml.safe_load((folder / "base.yaml").read_text())["seed"] == 1  # the file untouched


@pytest.mark.parametrize(
    ("setting", "expected"),
    [
        ("nokey", "--set: expected KEY=VALUE"),
        ("=3", "--set: expected KEY=VALUE"),
        ("engine.codex=vp8", "--set (engine.codex): unknown key 'codex' in engine"),
        ("engine.codec=bogus", "--set (engine.codec): expected a full-frame codec"),
        ("engine.codec=[a", "--set engine.codec:1: invalid YAML"),
        ("route[3].trace=x.csv", "--set (route[3].trace): route has no item [3]"),
    ],
)
def test_a_bad_setting_is_one_line_and_exit_2(folder, capsys, setting, expected):
    out = folder / "out"
    argv = ["run", str(folder / "base.yaml"), "--out", str(out), "--quiet", "--set", setting]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"uma: error: {expected}"), err
    assert err.count("\n") == 1
    assert not out.exists()


def test_a_key_set_twice_is_refused(folder, capsys):
    argv = ["run", str(folder / "base.yaml"), "--set", "seed=2", "--set", "seed=3"]
    assert main(argv) == 2
    assert "--set (seed): given twice" in capsys.readouterr().err


def test_a_relative_path_is_read_from_the_current_folder(folder, capsys, monkeypatch):
    here = folder / "here"
    here.mkdir()
    monkeypatch.chdir(here)
    argv = ["run", str(folder / "base.yaml"), "--set", "route[0].trace=missing.csv"]
    assert main(argv) == 2
    assert str(here / "missing.csv") in capsys.readouterr().err
