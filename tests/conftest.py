"""Shared fixtures: the real data beside the clone (`../shared/data`), skipped when absent."""

from __future__ import annotations

from pathlib import Path

import pytest

from uma.paths import shared_data_dir


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """`../shared/data`; tests that take it skip on a clone without the shared folder."""
    root = shared_data_dir()
    if not root.is_dir():
        pytest.skip(f"shared data not found at {root}")
    return root
