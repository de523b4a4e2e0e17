"""The tiny scenario file the API tests share."""

import pytest
from api_scenario import TINY


@pytest.fixture
def scenario_file(tmp_path):
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY)
    return path
