"""Experiments at scale: sweeps over scenario grids (local processes or Dask) and the
regression gate against baselines kept in the repository. No SimPy here: points run through
`uma.sim` in worker processes."""

from uma.experiments.executor import DaskExecutor, Executor, LocalExecutor, make_executor
from uma.experiments.spec import Experiment, Point, load_experiment, scenario_hash
from uma.experiments.sweep import SweepResult, run_sweep

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
