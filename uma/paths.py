"""Where the project's data folders live (`codecs/`, `scenarios/`, `traces/` at the project root).

The package is installed in editable mode from the clone, so the data folders sit beside it.
`UMA_HOME` overrides the root, for an installed copy that keeps its data elsewhere.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["project_root", "codecs_dir", "scenarios_dir", "traces_dir", "shared_data_dir"]


def project_root() -> Path:
    """The folder holding `codecs/`, `scenarios/` and `traces/`."""
    env = os.environ.get("UMA_HOME")
    return Path(env) if env else Path(__file__).resolve().parent.parent


def codecs_dir() -> Path:
    return project_root() / "codecs"


def scenarios_dir() -> Path:
    return project_root() / "scenarios"


def traces_dir() -> Path:
    return project_root() / "traces"


def shared_data_dir() -> Path:
    """`../shared/data` beside the clone (real traces and faces), or `UMA_SHARED_DATA`; may not exist."""
    env = os.environ.get("UMA_SHARED_DATA")
    return Path(env) if env else project_root().parent / "shared" / "data"
