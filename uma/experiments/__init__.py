"""Experiments at scale: sweeps over scenario grids (local processes or Dask) and the
regression gate against baselines kept in the repository. No SimPy here: points run through
`uma.sim` in worker processes.

The names below are imported from their modules at first use: a spawned worker that unpickles
`executor.end_with_parent` (every local sweep's initializer) loads the executor alone, not the
simulation the sweep module imports.
"""

import importlib

_HOMES = {
    "Executor": "uma.experiments.executor",
    "LocalExecutor": "uma.experiments.executor",
    "DaskExecutor": "uma.experiments.executor",
    "make_executor": "uma.experiments.executor",
    "Experiment": "uma.experiments.spec",
    "Point": "uma.experiments.spec",
    "load_experiment": "uma.experiments.spec",
    "scenario_hash": "uma.experiments.spec",
    "SweepResult": "uma.experiments.sweep",
    "run_sweep": "uma.experiments.sweep",
}

__all__ = [
    "Executor",
    "LocalExecutor",
    "DaskExecutor",
    "make_executor",
    "Experiment",
    "Point",
    "load_experiment",
    "scenario_hash",
    "SweepResult",
    "run_sweep",
]


def __getattr__(name: str):
    """One of `__all__`, imported from its module at first use."""
    if name in _HOMES:
        value = getattr(importlib.import_module(_HOMES[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'uma.experiments' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
