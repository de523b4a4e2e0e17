"""A resumed sweep reads each point's metrics.json: what is no finished run's (a FIFO, a
symlink loop, JSON nested past the recursion limit, not an object) reads as not done."""

import os

import pytest

from uma.experiments.point import completed_metrics


@pytest.mark.parametrize("make", ["fifo", "loop", "deep", "list", "empty"])
def test_what_is_no_finished_run_is_not_done(tmp_path, make):
    path = tmp_path / "metrics.json"
    if make == "fifo":
        os.mkfifo(path)
    elif make == "loop":
        path.symlink_to(path)
    elif make == "deep":
        path.write_text('{"a":' * 100_000 + "1" + "}" * 100_000)
    elif make == "list":
        path.write_text("[1, 2]")
    else:
        path.write_text("")
    assert completed_metrics(tmp_path) is None


def test_a_finished_run_is_done(tmp_path):
    (tmp_path / "metrics.json").write_text('{"freeze_ratio": 0.5}')
    assert completed_metrics(tmp_path) == {"freeze_ratio": 0.5}
