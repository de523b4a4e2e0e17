"""The Python API for notebooks: run a scenario, read results as pandas DataFrames, sweep.

`uma.run`, `uma.read_run`, `uma.sweep`, `uma.read_sweep` and `uma.Run` (the package's top level
imports this room lazily). Errors are the CLI's: `UmaError` subclasses with its one-line
messages. Reference: docs/api.md.
"""

from uma.api.runs import RESULT_FILES, Run, read_run, run
from uma.api.sweeps import read_sweep, sweep

__all__ = ["Run", "run", "read_run", "sweep", "read_sweep", "RESULT_FILES"]
