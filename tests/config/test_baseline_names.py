"""Bad estimator and playout names, and a Salsify scenario without its trace: one line, exit 2."""

import shutil

import pytest

from uma.cli import main
from uma.paths import scenarios_dir

BASE = """\
name: t
route:
  - {technology: WLAN, duration_s: 2}
"""


def one_error_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("uma: error: ")
    return err[0]


@pytest.mark.parametrize(
    ("extra", "key", "names"),
    [
        ("engine: {estimator: foo}\n", "(engine.estimator)", "uma, gcc, webrtc"),
        (
            "engine:\n  estimator: {kind: foo}\n",
            "(engine.estimator.kind)",
            "'uma', 'gcc' or 'webrtc'",
        ),
        ("receiver: {playout: foo}\n", "(receiver.playout)", "'fixed' or 'adaptive'"),
    ],
)
def test_unknown_name_names_the_key(tmp_path, capsys, extra, key, names):
    path = tmp_path / "s.yaml"
    path.write_text(BASE + extra)
    assert main(["run", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    line = one_error_line(capsys)
    assert key in line and names in line and "'foo'" in line
    assert f"{path}:" in line
    assert not (tmp_path / "out").exists()


def test_estimator_shorthand_and_mapping_agree(tmp_path):
    from uma.config import load_scenario

    short = tmp_path / "a.yaml"
    short.write_text(BASE + "engine: {estimator: webrtc}\n")
    full = tmp_path / "b.yaml"
    full.write_text(BASE + "engine:\n  estimator: {kind: webrtc, initial_kbps: 300}\n")
    assert load_scenario(short).engine.estimator == load_scenario(full).engine.estimator
    assert load_scenario(short).engine.estimator.kind == "webrtc"


def test_salsify_scenario_without_its_trace(tmp_path, capsys):
    # Copied away from the project, the scenario's relative trace path points nowhere.
    path = tmp_path / "salsify-tmobile-umts.yaml"
    shutil.copy(scenarios_dir() / "salsify-tmobile-umts.yaml", path)
    assert main(["run", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    line = one_error_line(capsys)
    assert "(route[0].trace)" in line and "TMobile-UMTS-driving.down" in line
    assert "expected an existing file" in line


def test_bench_salsify_missing_trace(tmp_path, capsys):
    missing = tmp_path / "nope.down"
    assert main(["bench", "salsify", "--trace", str(missing), "--frames", "10"]) == 2
    line = one_error_line(capsys)
    assert str(missing) in line and "--trace" in line
