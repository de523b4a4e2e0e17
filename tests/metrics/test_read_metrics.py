"""`read_metrics`: a missing file is None; anything that is not a run's metrics is one line."""

import os

import pytest

from uma.errors import ConfigError
from uma.metrics.results import read_metrics


def test_missing_file_is_none(tmp_path):
    assert read_metrics(tmp_path / "metrics.json") is None


def test_metrics_round_trip(tmp_path):
    path = tmp_path / "metrics.json"
    path.write_text('{"freeze_ratio": 0.1}')
    assert read_metrics(path) == {"freeze_ratio": 0.1}


def test_fifo_is_refused_without_blocking(tmp_path):
    path = tmp_path / "metrics.json"
    os.mkfifo(path)
    with pytest.raises(ConfigError, match="metrics.json"):
        read_metrics(path)


def test_symlink_loop_is_one_line(tmp_path):
    path = tmp_path / "metrics.json"
    path.symlink_to(path)
    with pytest.raises(ConfigError, match="symlink loop"):
        read_metrics(path)


def test_json_nested_too_deep_is_one_line(tmp_path):
    path = tmp_path / "metrics.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ConfigError, match="nested too deeply"):
        read_metrics(path)
