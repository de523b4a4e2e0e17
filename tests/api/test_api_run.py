"""`uma.run`, `Run` and `uma.read_run` on one shared short run: the tables are the files' bytes."""

import json

import numpy as np
import pytest
from api_scenario import TINY

import uma
from uma.api import RESULT_FILES
from uma.errors import ConfigError, OutputError


@pytest.fixture(scope="module")
def shared(tmp_path_factory):
    """One run with two overrides, and the same run by the command line, for every test here."""
    from uma.cli import main

    folder = tmp_path_factory.mktemp("api")
    (folder / "tiny.yaml").write_text(TINY)
    (folder / "adaptive.yaml").write_text(
        TINY.replace("seed: 2", "seed: 5") + "receiver: {playout: adaptive}\n"
    )
    run = uma.run(folder / "tiny.yaml", seed=5, overrides={"receiver.playout": "adaptive"})
    cli = folder / "cli"
    assert main(["run", str(folder / "adaptive.yaml"), "--out", str(cli), "--quiet"]) == 0
    return run, folder, cli


def test_run_applies_the_overrides_and_returns_the_metrics(shared):
    run, _, _ = shared
    metrics = run.metrics
    assert metrics["seed"] == 5 and metrics["playout"] == "adaptive"
    assert run.scenario.receiver.playout == "adaptive" and run.scenario.seed == 5
    assert metrics["frames"] == len(run.frames) == 60
    assert run.folder is None and "tiny" in repr(run)


def test_summary_is_what_the_command_line_prints(shared, capsys):
    from uma.cli import main

    run, folder, _ = shared
    out = folder / "printed"
    assert main(["run", str(folder / "adaptive.yaml"), "--out", str(out)]) == 0
    assert uma.read_run(out).summary() == capsys.readouterr().out.rstrip("\n")
    assert run.summary().endswith("results   (not saved)")


def test_the_files_are_the_ones_the_command_line_writes(shared):
    run, _, cli = shared
    for name in ("metrics.json", "frames.csv", "events.csv"):
        assert run.file_bytes(name) == (cli / name).read_bytes(), name


def test_frames_and_events_equal_the_csv_files_save_writes(shared, tmp_path):
    from uma.report.results import read_run as read_with_csv_module

    run, _, _ = shared
    out = run.save(tmp_path / "saved")
    files = read_with_csv_module(out)  # the report's reader: the csv module, not pandas
    frames = run.frames
    assert list(frames.columns) == (out / "frames.csv").read_text().splitlines()[0].split(",")
    for name, values in files.frames.items():
        if values.dtype.kind == "f":
            np.testing.assert_array_equal(frames[name].to_numpy(dtype=float), values, err_msg=name)
        else:
            assert frames[name].astype(str).tolist() == values.tolist(), name
    assert frames["frame"].dtype == np.int64 and frames["delay_ms"].dtype == np.float64
    events = run.events
    assert list(events.itertuples(index=False, name=None)) == files.events
    assert run.metrics == files.metrics == json.loads((out / "metrics.json").read_text())


def test_read_run_round_trip(shared, tmp_path):
    run, _, _ = shared
    back = uma.read_run(run.save(tmp_path / "r"))
    assert back.folder == tmp_path / "r"
    assert back.frames.equals(run.frames) and back.events.equals(run.events)
    assert back.metrics == run.metrics
    assert back.scenario == run.scenario
    for name in RESULT_FILES:
        assert back.file_bytes(name) == run.file_bytes(name)


def test_tables_are_new_at_each_access(shared):
    run, _, _ = shared
    frames = run.frames
    frames["psnr_db"] = 0.0
    assert (run.frames["psnr_db"] != 0.0).any()
    metrics = run.metrics
    metrics["seed"] = 99
    assert run.metrics["seed"] == 5


def test_save_refuses_a_folder_holding_other_files_and_leaves_it_whole(shared, tmp_path):
    run, _, _ = shared
    target = tmp_path / "mine"
    target.mkdir()
    (target / "notes.txt").write_text("keep me")
    with pytest.raises(OutputError, match=r"Run.save: .*notes.txt"):
        run.save(target)
    assert sorted(p.name for p in target.iterdir()) == ["notes.txt"]
    assert (target / "notes.txt").read_text() == "keep me"


def test_save_replaces_an_earlier_run_whole(shared, tmp_path):
    run, _, cli = shared
    target = tmp_path / "again"
    run.save(target)
    (target / "frames.csv").write_text("frame\n")  # damaged since
    run.save(target)
    assert (target / "frames.csv").read_bytes() == run.file_bytes("frames.csv")
    assert sorted(p.name for p in target.iterdir()) == sorted(RESULT_FILES)


def test_a_save_that_fails_leaves_the_earlier_run_whole_and_no_leftovers(
    shared, tmp_path, monkeypatch
):
    import uma.atomic

    run, _, _ = shared
    target = tmp_path / "earlier"
    run.save(target)
    (target / "metrics.json").write_text('{"an": "earlier run"}\n')
    before = {name: (target / name).read_bytes() for name in RESULT_FILES}

    def disk_full(folder):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(uma.atomic, "_fsync_tree", disk_full)
    with pytest.raises(OutputError, match="No space left"):
        run.save(target)
    assert {name: (target / name).read_bytes() for name in RESULT_FILES} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["earlier"]


def test_file_bytes_names_the_files_it_has(shared):
    run, _, _ = shared
    with pytest.raises(ConfigError, match="Run.file_bytes: expected one of scenario.yaml"):
        run.file_bytes("timeline.png")


def test_save_into_a_file_is_an_output_error(shared, tmp_path):
    run, _, _ = shared
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputError, match="Run.save"):
        run.save(tmp_path / "file" / "below")
    with pytest.raises(ConfigError, match="Run.save: expected a folder path"):
        run.save("")


def test_timeline_is_the_reports_figure(shared):
    from matplotlib.figure import Figure

    run, _, _ = shared
    figure = run.timeline()
    assert isinstance(figure, Figure) and len(figure.axes) == 5


def test_read_run_names_what_is_wrong_with_a_folder(shared, tmp_path):
    run, _, _ = shared
    folder = run.save(tmp_path / "damaged")
    text = (folder / "frames.csv").read_text().splitlines()
    (folder / "frames.csv").write_text("\n".join(text[:5] + ["1,2,3"]) + "\n")
    with pytest.raises(ConfigError, match=r"frames.csv:6: expected 26 fields"):
        uma.read_run(folder)
    (folder / "frames.csv").unlink()
    with pytest.raises(ConfigError, match=r"frames.csv: missing"):
        uma.read_run(folder)
    with pytest.raises(ConfigError, match="expected a results folder"):
        uma.read_run(tmp_path / "absent")
    sweep = tmp_path / "sweep"
    sweep.mkdir()
    (sweep / "sweep.csv").write_text("point\n")
    with pytest.raises(ConfigError, match="uma.read_sweep"):
        uma.read_run(sweep)


def test_read_run_refuses_a_fifo_or_device_without_blocking(shared, tmp_path):
    import os

    run, _, _ = shared
    folder = run.save(tmp_path / "odd")
    (folder / "frames.csv").unlink()
    os.mkfifo(folder / "frames.csv")
    with pytest.raises(ConfigError, match=r"frames.csv: expected a result file, got a folder"):
        uma.read_run(folder)
    (folder / "frames.csv").unlink()
    (folder / "frames.csv").symlink_to("/dev/zero")
    with pytest.raises(ConfigError, match=r"frames.csv: expected a result file"):
        uma.read_run(folder)


def test_a_read_run_without_its_scenario_file_is_refused(shared, tmp_path):
    run, _, _ = shared
    folder = run.save(tmp_path / "noscenario")
    (folder / "scenario.yaml").unlink()
    with pytest.raises(ConfigError, match=r"scenario.yaml: missing"):
        uma.read_run(folder)


def test_out_writes_the_folder_and_a_foreign_file_is_refused_before_the_run(
    shared, tmp_path, monkeypatch
):
    import uma.sim

    _, folder, cli = shared
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "data.csv").write_text("x")

    def never(*args, **kwargs):
        raise AssertionError("the run started before --out was checked")

    monkeypatch.setattr(uma.sim, "run_scenario", never)
    with pytest.raises(OutputError, match=r"uma.run\(out=...\).*data.csv"):
        uma.run(folder / "adaptive.yaml", out=mine)
    assert sorted(p.name for p in mine.iterdir()) == ["data.csv"]
