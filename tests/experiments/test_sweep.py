"""Sweeps: grid expansion, resumption by hash, failures recorded, CSV = Parquet, and the same
results on a Dask LocalCluster (loopback) as on local processes."""

import re

import pytest
from sweep_files import EXPERIMENT

from uma.cli import main
from uma.errors import ConfigError
from uma.experiments import LocalExecutor, load_experiment, run_sweep
from uma.experiments.table import read_table_csv


def test_grid_expands_with_repeats_and_distinct_hashes(folder):
    (folder / "exp.yaml").write_text(EXPERIMENT + "repeat: 2\n")
    experiment = load_experiment(folder / "exp.yaml")
    assert len(experiment.points) == 8
    assert experiment.grid_keys == ("engine.policy", "receiver.playout_delay_ms")
    assert [p.scenario.seed for p in experiment.points[:2]] == [1, 2]
    assert len({p.hash for p in experiment.points}) == 8
    last = experiment.points[-1].scenario
    assert (last.engine.policy, last.receiver.playout_delay_ms) == ("oracle", 400)


@pytest.mark.parametrize(
    "grid, message",
    [
        (
            "grid:\n  engine.polcy: [a]\n",
            r"exp.yaml:4 \(grid.engine.polcy\): unknown key 'polcy' in engine",
        ),
        ("grid: {}\n", r"exp.yaml:3 \(grid\): expected a non-empty mapping"),
        ("grid:\n  route[5].trace: [a]\n", r"route has no item \[5\]"),
        (
            "grid:\n  engine.safety: []\n",
            r"exp.yaml:4 \(grid.engine.safety\): expected a non-empty list",
        ),
        (
            "grid:\n  engine.safety: [0.5, 2]\n",
            r"exp.yaml:4 \(grid.engine.safety\[1\]\): 2 is above the maximum 1 \(grid point",
        ),
    ],
)
def test_bad_experiments_are_one_config_error(folder, grid, message):
    (folder / "exp.yaml").write_text("name: grid\nbase: base.yaml\n" + grid)
    with pytest.raises(ConfigError, match=message):
        load_experiment(folder / "exp.yaml")


def test_sweep_cli_bad_grid_key_is_exit_2_and_writes_nothing(folder, capsys):
    (folder / "exp.yaml").write_text("name: grid\nbase: base.yaml\ngrid:\n  bogus: [1]\n")
    assert main(["sweep", str(folder / "exp.yaml"), "--out", str(folder / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "exp.yaml:4 (grid.bogus): unknown key 'bogus'" in err[0]
    assert not (folder / "out").exists()


def test_unreachable_scheduler_is_exit_2(folder, capsys):
    code = main(
        [
            "sweep",
            str(folder / "exp.yaml"),
            "--scheduler",
            "tcp://127.0.0.1:9",
            "--timeout",
            "1",
            "--out",
            str(folder / "o"),
        ]
    )
    assert code == 2
    assert re.search(
        r"--scheduler: cannot reach a Dask scheduler at 'tcp://127.0.0.1:9'",
        capsys.readouterr().err,
    )


def test_sweep_resumes_and_records_a_failed_point(folder, capsys):
    import pyarrow.parquet as pq

    (folder / "bad.csv").write_text("time_s,rate_kbps,technology\n0,fast,3G\n")
    (folder / "exp.yaml").write_text(
        "name: grid\nbase: base.yaml\ngrid:\n  route[0].trace: [good.csv, bad.csv]\n"
        "  engine.policy: [throughput, oracle]\n"
    )
    out = folder / "out"
    assert main(["sweep", str(folder / "exp.yaml"), "--out", str(out), "--workers", "2"]) == 1
    printed = capsys.readouterr().out
    assert "4 points, 4 run, 0 already complete, 2 failed" in printed
    rows = read_table_csv(out / "sweep.csv")
    assert [r["status"] for r in rows] == ["ok", "ok", "failed", "failed"]
    assert "line 2 of" in rows[2]["error"] and "bad.csv" in rows[2]["error"]
    assert rows[0]["route[0].trace"] == "good.csv" and float(rows[0]["frames"]) == 50
    table = pq.read_table(out / "sweep.parquet").to_pylist()
    assert [r["hash"] for r in table] == [r["hash"] for r in rows]
    assert table[0]["psnr_db"] == pytest.approx(float(rows[0]["psnr_db"]))
    first = (out / "sweep.csv").read_text()
    stamps = {
        p.name: (p / "metrics.json").stat().st_mtime_ns
        for p in (out / "points").iterdir()
        if (p / "metrics.json").exists()
    }

    (folder / "bad.csv").write_text("time_s,rate_kbps,technology\n0,300,3G\n")  # fixed: now runs
    assert main(["sweep", str(folder / "exp.yaml"), "--out", str(out)]) == 0
    assert "4 points, 2 run, 2 already complete, 0 failed" in capsys.readouterr().out
    for name, stamp in stamps.items():
        assert (out / "points" / name / "metrics.json").stat().st_mtime_ns == stamp
    again = read_table_csv(out / "sweep.csv")
    assert [r["status"] for r in again] == ["ok"] * 4
    assert first.splitlines()[1] == (out / "sweep.csv").read_text().splitlines()[1]


def test_dask_local_cluster_gives_the_local_results(folder):
    from distributed import LocalCluster

    from uma.experiments import DaskExecutor

    experiment = load_experiment(folder / "exp.yaml")
    local = LocalExecutor(2)
    try:
        by_processes = run_sweep(experiment, folder / "local", local)
    finally:
        local.close()
    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
        silence_logs=40,
    ) as cluster:
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        dask = DaskExecutor(cluster.scheduler_address)
        try:
            by_dask = run_sweep(experiment, folder / "dask", dask)
        finally:
            dask.close()
    assert by_dask.ran == by_processes.ran == 4 and by_dask.failed == 0
    assert by_dask.rows == by_processes.rows
    assert (folder / "dask" / "sweep.csv").read_bytes() == (
        folder / "local" / "sweep.csv"
    ).read_bytes()
    for point in experiment.points:
        for name in ("frames.csv", "metrics.json"):
            a = (folder / "local" / "points" / point.hash / name).read_bytes()
            assert a == (folder / "dask" / "points" / point.hash / name).read_bytes()


def test_shipped_experiment_loads():
    from uma.paths import scenarios_dir

    experiment = load_experiment(scenarios_dir() / "experiments" / "policy-playout.yaml")
    assert len(experiment.points) == 8 and experiment.name == "policy-playout"


def test_key_paths_reach_nested_and_mapping_keys(folder):
    (folder / "exp.yaml").write_text(
        "name: g\nbase: base.yaml\ngrid:\n  downlink.technologies.GPRS.delay_ms: [100, 400]\n"
        "  engine.estimator.min_kbps: [12]\n  engine.stale_reports: [2]\n"
    )
    points = load_experiment(folder / "exp.yaml").points
    assert [p.scenario.downlink.technologies["GPRS"].delay_ms for p in points] == [100, 400]
    assert points[0].scenario.engine.estimator.min_kbps == 12
    assert points[0].scenario.engine.stale_reports == 2
