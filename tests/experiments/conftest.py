"""The folder both sweep test modules run their small sweep in."""

import pytest
from sweep_files import BASE, EXPERIMENT


@pytest.fixture
def folder(tmp_path):
    """A folder holding `base.yaml`, its trace `good.csv` and the experiment `exp.yaml`."""
    (tmp_path / "base.yaml").write_text(BASE)
    (tmp_path / "good.csv").write_text("time_s,rate_kbps,technology\n0,400,3G\n")
    (tmp_path / "exp.yaml").write_text(EXPERIMENT)
    return tmp_path
