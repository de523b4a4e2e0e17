import subprocess
import sys

import pytest

from uma.cli import main


def test_help_lists_commands(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--help"])
    assert exit_info.value.code == 0
    out = capsys.readouterr().out
    assert "run" in out and "bench" in out


def test_bad_scenario_is_one_line_and_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nroute:\n  - {technology: WLAN, duration_s: -3}\n")
    assert main(["run", str(bad), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("uma: error: ") and "route[0].duration_s" in err[0]
    assert not (tmp_path / "out").exists()


def test_missing_scenario_file_exit_2(tmp_path, capsys):
    assert main(["run", str(tmp_path / "nope.yaml")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_help_is_light():
    # `uma --help` must not import the heavy libraries.
    code = (
        "import sys; from uma.cli import build_parser; build_parser(); "
        "heavy = [m for m in ('av', 'cv2', 'skimage', 'simpy', 'numba', 'dask', 'matplotlib', 'aiortc') "
        "if m in sys.modules]; print(heavy)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_malformed_trace_in_scenario_names_file_and_line(tmp_path, capsys):
    trace = tmp_path / "t.csv"
    trace.write_text("time_s,rate_kbps,technology\n0,100,3G\n1,lots,3G\n")
    scenario = tmp_path / "s.yaml"
    scenario.write_text("name: x\nroute:\n  - {technology: 3G, duration_s: 2, trace: t.csv}\n")
    assert main(["run", str(scenario), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "line 3 of" in err[0] and "t.csv" in err[0]
    assert not (tmp_path / "out" / "metrics.json").exists()


def test_run_out_that_is_a_file_fails_before_the_run(tmp_path, capsys, monkeypatch):
    import uma.sim

    def never(*args, **kwargs):
        raise AssertionError("the simulation ran")

    monkeypatch.setattr(uma.sim, "run_scenario", never)
    taken = tmp_path / "taken"
    taken.write_text("x")
    scenario = tmp_path / "s.yaml"
    scenario.write_text("name: x\nroute:\n  - {technology: 3G, duration_s: 1}\n")
    assert main(["run", str(scenario), "--out", str(taken), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"uma: error: --out: expected a folder for the results, got an existing file '{taken}'"
    ]
