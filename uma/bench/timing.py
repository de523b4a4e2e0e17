"""Wall-clock timing for the benchmarks (never the simulation): the median of repeated calls,
and the compiled kernels a timed part must not compile or load.

Units: milliseconds (`median_ms`), seconds (`warm_up`).

numba compiles a kernel (or, with `cache=True`, loads it from its cache) on the kernel's first
call with new argument types: seconds in a fresh checkout, tens of milliseconds per kernel
after. A bench calls `warm_up` before its timed part and reports the seconds apart; then
`kernels_loaded_since` names any kernel the timed part still had to compile or load (none,
when the warm-up covered every path the timed part takes).
"""

from __future__ import annotations

import importlib
import time
from collections.abc import Callable

import numpy as np

__all__ = ["median_ms", "KERNEL_MODULES", "kernel_signatures", "kernels_loaded_since", "warm_up"]

# Every module of the project that holds numba kernels.
KERNEL_MODULES = (
    "uma.fit.kernels",
    "uma.fit.photometry",
    "uma.face.raster_kernels",
    "uma.face.talking_head_kernels",
    "uma.mbc.block_kernels",
    "uma.mbc.fill_kernels",
    "uma.mbc.layered_kernels",
    "uma.metrics.ssim_kernel",
)


def median_ms(fn: Callable[[], object], repeats: int = 30) -> float:
    """The median wall time of `repeats` calls of `fn`, in ms (a median: this machine is noisy)."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times) * 1000.0)


def kernel_signatures(modules: tuple[str, ...] = KERNEL_MODULES) -> dict[str, frozenset[str]]:
    """Every kernel of `modules` ("module.name") and the argument types it has been compiled
    or loaded for in this process so far."""
    out = {}
    for name in modules:
        module = importlib.import_module(name)
        for attr, value in vars(module).items():
            if hasattr(value, "py_func") and hasattr(value, "signatures"):
                out[f"{name}.{attr}"] = frozenset(str(s) for s in value.signatures)
    return out


def kernels_loaded_since(
    before: dict[str, frozenset[str]], modules: tuple[str, ...] = KERNEL_MODULES
) -> list[str]:
    """The kernels of `modules` compiled or loaded for new argument types since `before`
    (`kernel_signatures(modules)`), as "module.name(types)", sorted."""
    now = kernel_signatures(modules)
    return sorted(
        f"{name}{signature}"
        for name, signatures in now.items()
        for signature in signatures - before.get(name, frozenset())
    )


def warm_up(work: Callable[[], object]) -> float:
    """Run `work` (untimed calls that reach every kernel the timed part will call, with the
    same argument types) and return its wall seconds: the compile or cache-load time."""
    start = time.perf_counter()
    work()
    return time.perf_counter() - start
