"""Shared fixtures: the real data beside the clone (`../shared/data`), skipped when absent.

Hypothesis profiles: `ci` is derandomised (the same examples every run, so a CI failure is
about the change, not the draw), chosen by `HYPOTHESIS_PROFILE=ci` (as `.ci/run` sets) or by
`CI` being set; local runs keep `dev`, which draws new examples each time.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

from uma.paths import shared_data_dir

settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
# Explicit: with `CI` set, Hypothesis loads its own derandomised `ci` profile at import, and a
# profile registered without values would inherit it.
settings.register_profile("dev", derandomize=False)
settings.load_profile(
    os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if os.environ.get("CI") else "dev")
)


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """`../shared/data`; tests that take it skip on a clone without the shared folder."""
    root = shared_data_dir()
    if not root.is_dir():
        pytest.skip(f"shared data not found at {root}")
    return root
