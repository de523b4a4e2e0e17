"""`uma.sweep` and `uma.read_sweep` on a two-point sweep: the table is the sweep's Parquet file."""

import pytest
from api_scenario import TINY

import uma
from uma.errors import ConfigError

EXPERIMENT = """\
name: two
base: tiny.yaml
set: {duration_s: 1.0}
grid:
  receiver.playout_delay_ms: [150, 400]
"""


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    (folder / "tiny.yaml").write_text(TINY)
    (folder / "exp.yaml").write_text(EXPERIMENT)
    table = uma.sweep(folder / "exp.yaml", workers=1, out=folder / "out")
    return table, folder


def test_sweep_returns_its_table_one_row_a_point(swept):
    table, _ = swept
    assert table["receiver.playout_delay_ms"].tolist() == [150, 400]
    assert table["status"].tolist() == ["ok", "ok"]
    assert (table["frames"] == 25).all() and "freeze_ratio" in table.columns


def test_read_sweep_reads_the_parquet_file_the_csv_agrees_with(swept):
    import pandas as pd

    table, folder = swept
    read = uma.read_sweep(folder / "out")
    pd.testing.assert_frame_equal(read, table)
    csv = pd.read_csv(folder / "out" / "sweep.csv")
    assert csv["hash"].tolist() == read["hash"].tolist()
    assert csv["freeze_ratio"].tolist() == read["freeze_ratio"].tolist()


def test_a_sweep_again_runs_nothing_and_gives_the_same_table(swept):
    import pandas as pd

    table, folder = swept
    before = {p.name: p.stat().st_mtime_ns for p in (folder / "out" / "points").iterdir()}
    again = uma.sweep(folder / "exp.yaml", workers=1, out=folder / "out")
    pd.testing.assert_frame_equal(again, table)
    after = {p.name: p.stat().st_mtime_ns for p in (folder / "out" / "points").iterdir()}
    assert after == before


def test_a_points_folder_reads_as_a_run(swept):
    table, folder = swept
    run = uma.read_run(folder / "out" / "points" / table["hash"][0])
    assert run.metrics["freeze_ratio"] == table["freeze_ratio"][0]


def test_a_damaged_table_is_a_config_error(tmp_path):
    (tmp_path / "sweep.parquet").write_bytes(b"PAR1 not really")
    with pytest.raises(ConfigError, match=r"sweep.parquet: expected a sweep table in Parquet"):
        uma.read_sweep(tmp_path)


def test_a_fifo_for_a_table_is_refused_without_blocking(tmp_path):
    import os

    os.mkfifo(tmp_path / "sweep.parquet")
    with pytest.raises(ConfigError, match=r"sweep.parquet: expected a sweep table in Parquet, got"):
        uma.read_sweep(tmp_path)


def test_a_sweep_into_one_runs_folder_is_refused(swept, tmp_path):
    _, folder = swept
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    (run_dir / "metrics.json").write_text("{}")
    with pytest.raises(ConfigError, match=r"holds the results of one run"):
        uma.sweep(folder / "exp.yaml", workers=1, out=run_dir)
    assert sorted(p.name for p in run_dir.iterdir()) == ["metrics.json"]
