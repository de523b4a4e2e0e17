"""The command line's tests: a folder holding `base.yaml` and `exp.yaml` (`cli_folder`)."""

import pytest
from cli_folder import BASE, EXPERIMENT


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "base.yaml").write_text(BASE)
    (tmp_path / "exp.yaml").write_text(EXPERIMENT)
    return tmp_path
