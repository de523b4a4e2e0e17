"""`uma.sweep` and `uma.read_sweep`: an experiment's grid run as `uma sweep` runs it, its table
as a pandas DataFrame.

The table is the sweep's `sweep.parquet`: one row per run, the grid's key paths, `seed`,
`status` (`ok`, `failed`, `missing`), `error`, then every metric of `metrics.json` (nested keys
joined by dots: `by_technology.GSM.freeze_ratio`), units in the names.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

from uma.errors import ConfigError

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["sweep", "read_sweep"]


def read_sweep(folder: str | os.PathLike) -> pd.DataFrame:
    """The table of the sweep in `folder` (as `uma sweep --out` wrote it) as a DataFrame."""
    from uma.api.runs import folder_path
    from uma.api.tables import sweep_frame

    path = folder_path(folder, "uma.read_sweep")
    if not path.is_dir():
        raise ConfigError(f"{path}: expected a sweep's results folder (as `uma sweep` writes)")
    return sweep_frame(path / "sweep.parquet")


def _refuse_run_folder(folder: Path) -> None:
    """A sweep never writes into one run's results: the folder would mix two kinds of result."""
    from uma.api.runs import RESULT_FILES

    if any((folder / name).exists() for name in RESULT_FILES):
        raise ConfigError(
            f"uma.sweep(out=...): {str(folder)!r} holds the results of one run (uma run); "
            f"expected an empty folder or a sweep's"
        )


def _workers(workers: Any) -> int:
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ConfigError(f"uma.sweep(workers=...): expected a positive integer, got {workers!r}")
    return workers


def sweep(
    experiment: str | os.PathLike,
    *,
    workers: int = 2,
    out: str | os.PathLike | None = None,
    scheduler: str | None = None,
) -> pd.DataFrame:
    """Run every point of experiment file `experiment` not yet complete in `out`; its table.

    As `uma sweep`: `out` defaults to `results/<name>`, points run on `workers` local processes
    (or the Dask cluster at `scheduler`), points already complete are not run again, a failed
    point is a row with status `failed` and its error (and a warning here) while the others go
    on. Bad input is a `ConfigError` before anything runs. Ctrl-C stops the workers and
    raises `KeyboardInterrupt`, the table then listing the points not run as `missing`.
    """
    from uma.api.runs import folder_path
    from uma.atomic import prepare_out_dir
    from uma.experiments import load_experiment, make_executor, run_sweep

    path = folder_path(experiment, "uma.sweep", "an experiment file path")
    count = _workers(workers) if scheduler is None else None
    if scheduler is not None and not isinstance(scheduler, str):
        raise ConfigError(f"uma.sweep(scheduler=...): expected an address, got {scheduler!r}")
    loaded = load_experiment(path)
    target = (
        Path("results") / loaded.name if out is None else folder_path(out, "uma.sweep(out=...)")
    )
    out_dir = prepare_out_dir(target, what="uma.sweep(out=...)")
    _refuse_run_folder(out_dir)
    executor = make_executor(workers=count, scheduler=scheduler)
    try:
        result = run_sweep(loaded, out_dir, executor)
    except KeyboardInterrupt:
        executor.terminate()
        raise
    finally:
        executor.close()
    if result.failed:
        warnings.warn(
            f"uma.sweep: {result.failed} of {len(result.rows)} points failed; see the table's "
            f"status and error columns",
            RuntimeWarning,
            stacklevel=2,
        )
    return read_sweep(out_dir)
