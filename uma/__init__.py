"""uma: a video conference over a roaming mobile downlink, simulated with real codecs and traces.

The Python API (docs/api.md): `uma.run(scenario, seed=..., out=..., overrides=..., **keys)`
returns a `uma.Run` (`.metrics`, `.frames`, `.events`, `.scenario`, `.timeline()`, `.save()`);
`uma.read_run(folder)`, `uma.sweep(experiment)`, `uma.read_sweep(folder)`. They live in
`uma.api` and are imported at first use, so `import uma` (and `uma --help`) stays instant.

Sub-packages hold one job each (docs/architecture.md): `traces`, `video`, `face`, `fit`,
`engine`, `sim`, `metrics`, `experiments`, `report`, `bench`, `cli`.

Importing uma pins OpenBLAS's kernel set and its thread count (one) before NumPy loads
(`uma.blas`), so a seed gives the same figures on other machines with AVX2, whatever their
number of cores (docs/experiments.md says how far that is shown), keeps OpenCV and NumPy off
their AVX-512 paths where the CPU has them (the same figures as on an AVX2 machine), and runs
OpenCV on one thread a process unless told otherwise (`OPENCV_FOR_THREADS_NUM`). NumPy or
OpenCV imported before uma is too late for that: `import uma` then warns (a `RuntimeWarning`
naming them), since a seed's figures may differ from `uma run`'s.
"""

from uma.blas import pin_all


def _pin() -> None:
    """`uma.blas.pin_all`, and a `RuntimeWarning` naming NumPy or OpenCV if either was imported
    before uma where a pin would have reached it."""
    late = pin_all()
    if late:
        import warnings

        warnings.warn(
            f"uma: {' and '.join(late)} imported before uma, too late to pin its code paths "
            "(uma.blas): a seed's figures may differ from `uma run`'s; import uma first",
            RuntimeWarning,
            stacklevel=3,
        )


_pin()

from uma.errors import (  # noqa: E402
    ConfigError,
    FaceError,
    OutputError,
    RunError,
    TraceError,
    UmaError,
    VideoError,
)

__version__ = "0.1.0"

_API = frozenset({"Run", "run", "read_run", "sweep", "read_sweep"})

__all__ = [
    "run",
    "read_run",
    "sweep",
    "read_sweep",
    "Run",
    "UmaError",
    "ConfigError",
    "TraceError",
    "VideoError",
    "FaceError",
    "RunError",
    "OutputError",
    "__version__",
]


def __getattr__(name: str):
    """The API's names, imported from `uma.api` at first use (it pulls in pandas and SimPy)."""
    if name in _API:
        import importlib

        value = getattr(importlib.import_module("uma.api"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'uma' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | _API)
