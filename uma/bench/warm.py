"""Compile numba's kernels into their on-disk cache once, as `make install` does.

The kernels are compiled with `cache=True`: the first process that calls one compiles it and
writes it beside its module (`__pycache__`, or `NUMBA_CACHE_DIR`); later processes load it.
On a fresh clone every process would compile them on its first call, each of `make test`'s
workers on its own, so `make install` runs `python -m uma.bench.warm` after building the
venv: the same untimed calls as `uma bench sim`'s warm-up (`uma.bench.sim.warm_kernels`: the
scores, the tracker's start and tracking, the receiver's rendering and the model path) on a few
frames of the default scenario's talking head, after importing every kernel module (those
with declared types compile as they load). A kernel's cache follows its source file: one
edited later compiles again on its next call, as before.
"""

from __future__ import annotations

import importlib
import sys
import time

__all__ = ["WARM_SIZE", "warm_default_kernels", "main"]

# QCIF: the kernels compile for argument types, not sizes, and the smaller picture is quicker.
WARM_SIZE = (176, 144)
WARM_FRAMES = 3


def warm_default_kernels() -> float:
    """Compile (or load) the kernels the default scenario calls, and those compiled for their
    declared types when their module loads (`KERNEL_MODULES`); the wall seconds it took."""
    from uma.bench.sim import warm_kernels
    from uma.bench.timing import KERNEL_MODULES
    from uma.config.load import load_scenario

    start = time.perf_counter()
    for name in KERNEL_MODULES:
        importlib.import_module(name)
    width, height = WARM_SIZE
    warm_kernels(load_scenario(None), width=width, height=height, frames=WARM_FRAMES)
    return time.perf_counter() - start


def main() -> int:
    seconds = warm_default_kernels()
    print(f"uma: numba kernels compiled or loaded in {seconds:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
