"""One OpenBLAS kernel set and one thread on every machine, so a seed gives the same bits.

NumPy's and SciPy's wheels carry OpenBLAS, which picks its kernels from the CPU when it loads
(`Haswell` on an AVX2 CPU, `SkylakeX` on one with AVX-512, ...). Kernels sum a product in
different orders, so the same seed gave other figures on another machine: a rendered face moved
by a last bit, and the runs drifted apart from there (docs/experiments.md). `pin_kernels`, which
`import uma` calls first, sets `OPENBLAS_CORETYPE` to `Haswell` (AVX2 and FMA) before NumPy
loads, on every CPU that can run those kernels. It leaves OpenBLAS's own choice when the
variable is already set (a user's or a check's choice), when NumPy was imported before uma
(too late: `uma.experiments.machine.blas_core` records what ran), and on a CPU without AVX2
and FMA (the kernels would not run there). Child processes inherit the variable.

`pin_blas_threads`, called beside it, sets `OPENBLAS_NUM_THREADS` to 1 under the same rules (not
when the user chose a thread count through it, `GOTO_NUM_THREADS` or `OMP_NUM_THREADS`, not
after NumPy). OpenBLAS splits a factorisation by its thread count, and one thread sums in
another order than several: a description fitted by SciPy's `least_squares` came out other in
its last bits on a 1-core machine than on a multi-core one. uma's processes are single-threaded
and a sweep runs one process a core (`--workers`), so BLAS threads only fought over the cores
(docs/experiments.md).

`pin_opencv_threads`, which `import uma` calls last, sets `OPENCV_FOR_THREADS_NUM` to 1 before
OpenCV loads: uma's processes (the simulation, every sweep worker, the benches) are
single-threaded and run side by side, and OpenCV's own pool (one thread a core) only
oversubscribes the cores under them; the pixels are the same either way (docs/mbc.md, branch
mbc25). It leaves the variable alone when set (the user's choice) and when OpenCV was imported
before uma (its pool is sized at load).

`pin_dispatch`, called beside them, keeps OpenCV and NumPy off their AVX-512 code paths on a CPU
that has AVX-512 (the five feature sets of OpenCV's `AVX512-SKX` and NumPy's `X86_V4`). Both
choose a path per function when they load, and the AVX-512 ones round some float results
otherwise: on such a machine the synthetic pattern's frames (OpenCV's float `warpAffine`,
`getRectSubPix`, `resize`), the gate's figures and the model codec's came out other than on an
AVX2 machine. With `OPENCV_CPU_DISABLE=AVX512-SKX`
and `NPY_DISABLE_CPU_FEATURES="X86_V4 AVX512_ICL AVX512_SPR"`, the gate and `uma bench mbc` give
every figure of the AVX2 machine's records (docs/experiments.md). The variables are left alone
when set (the user's choice), when the library was imported before uma (its paths are chosen),
and on a CPU without AVX-512, where OpenCV would print a line about a feature it cannot disable.

`loaded_too_late` names the libraries imported before uma that one of these pins would have
reached (OpenCV's thread count aside: it moves no pixel); `import uma` warns about them. A
script that imported NumPy first ran the links bench's case on the AVX-512 machine with
other figures than the bench's (docs/measured.md, section 21).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import TypeVar

__all__ = [
    "PINNED_BLAS_THREADS",
    "PINNED_CORE",
    "PINNED_OPENCV_THREADS",
    "cpu_flags",
    "cpuinfo_text",
    "loaded_too_late",
    "pin_all",
    "pin_blas_threads",
    "pin_dispatch",
    "pin_kernels",
    "pin_opencv_threads",
    "pinned_blas_threads",
    "pinned_core",
    "pinned_dispatch",
    "pinned_opencv_threads",
]

PINNED_CORE = "Haswell"
PINNED_OPENCV_THREADS = 1
_NEEDS = frozenset({"avx2", "fma"})  # what the Haswell kernels execute
_CPUINFO = Path("/proc/cpuinfo")
_T = TypeVar("_T", str, int)
PINNED_BLAS_THREADS = 1
# The AVX-512 paths each library skips: variable, its value, the module that reads it at load.
PINNED_DISPATCH = (
    ("OPENCV_CPU_DISABLE", "AVX512-SKX", "cv2"),
    ("NPY_DISABLE_CPU_FEATURES", "X86_V4 AVX512_ICL AVX512_SPR", "numpy"),
)
_AVX512 = frozenset({"avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl"})
# OpenBLAS reads its thread count from the first of these that is set.
_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


def cpu_flags(cpuinfo_text: str) -> frozenset[str]:
    """The feature flags of the first processor in `/proc/cpuinfo`'s text (empty if none)."""
    for line in cpuinfo_text.splitlines():
        key, sep, value = line.partition(":")
        if sep and key.strip() == "flags":
            return frozenset(value.split())
    return frozenset()


def cpuinfo_text(path: Path = _CPUINFO) -> str:
    """`/proc/cpuinfo`'s text, or "" where it cannot be read (another OS)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as stream:
            return stream.read(1 << 20)
    except OSError:
        return ""


def _pin(variable: str, value: _T | None) -> _T | None:
    """Set `variable` for this process and its children unless `value` is None; `value`."""
    if value is not None:
        os.environ[variable] = str(value)
    return value


def pinned_core(
    environ: Mapping[str, str], flags: frozenset[str], numpy_loaded: bool
) -> str | None:
    """The kernel set to pin, or None to leave OpenBLAS's own choice."""
    if "OPENBLAS_CORETYPE" in environ or numpy_loaded or not flags >= _NEEDS:
        return None
    return PINNED_CORE


def pin_kernels(flags: frozenset[str] | None = None) -> str | None:
    """Set `OPENBLAS_CORETYPE` for this process and its children; the set pinned, or None.
    `flags`: the CPU's (None: read from /proc/cpuinfo)."""
    flags = cpu_flags(cpuinfo_text()) if flags is None else flags
    return _pin("OPENBLAS_CORETYPE", pinned_core(os.environ, flags, "numpy" in sys.modules))


def pinned_blas_threads(environ: Mapping[str, str], numpy_loaded: bool) -> int | None:
    """The BLAS thread count to pin, or None to leave the user's (or OpenBLAS's) choice."""
    if numpy_loaded or any(name in environ for name in _THREAD_VARIABLES):
        return None
    return PINNED_BLAS_THREADS


def pin_blas_threads() -> int | None:
    """Set `OPENBLAS_NUM_THREADS` for this process and its children; the count, or None."""
    return _pin("OPENBLAS_NUM_THREADS", pinned_blas_threads(os.environ, "numpy" in sys.modules))


def pinned_opencv_threads(environ: Mapping[str, str], opencv_loaded: bool) -> int | None:
    """OpenCV's thread count to pin, or None to leave OpenCV's own choice."""
    if "OPENCV_FOR_THREADS_NUM" in environ or opencv_loaded:
        return None
    return PINNED_OPENCV_THREADS


def pin_opencv_threads() -> int | None:
    """Set `OPENCV_FOR_THREADS_NUM` for this process and its children; the count, or None."""
    return _pin("OPENCV_FOR_THREADS_NUM", pinned_opencv_threads(os.environ, "cv2" in sys.modules))


def pinned_dispatch(
    environ: Mapping[str, str], flags: frozenset[str], loaded: frozenset[str]
) -> dict[str, str]:
    """The variables of `PINNED_DISPATCH` to set (the modules in `loaded` were imported)."""
    if not flags >= _AVX512:
        return {}
    return {
        variable: value
        for variable, value, module in PINNED_DISPATCH
        if variable not in environ and module not in loaded
    }


def pin_dispatch(flags: frozenset[str] | None = None) -> dict[str, str]:
    """Set the variables `pinned_dispatch` names for this process and its children; them.
    `flags`: the CPU's (None: read from /proc/cpuinfo)."""
    flags = cpu_flags(cpuinfo_text()) if flags is None else flags
    pinned = pinned_dispatch(os.environ, flags, frozenset(sys.modules))
    for variable, value in pinned.items():
        _pin(variable, value)
    return pinned


def loaded_too_late(
    environ: Mapping[str, str], flags: frozenset[str], loaded: frozenset[str]
) -> tuple[str, ...]:
    """The modules of `loaded` (imported before uma) that a pin would have reached had they not
    been: NumPy (OpenBLAS's kernels or threads, NumPy's AVX-512 paths) and OpenCV (its
    AVX-512 paths); a seed's figures may then differ from a process that imported uma first."""
    would_pin = pinned_dispatch(environ, flags, frozenset())
    late = []
    numpy_pins = (
        pinned_core(environ, flags, numpy_loaded=False) is not None
        or pinned_blas_threads(environ, numpy_loaded=False) is not None
        or "NPY_DISABLE_CPU_FEATURES" in would_pin
    )
    if "numpy" in loaded and numpy_pins:
        late.append("numpy")
    if "cv2" in loaded and "OPENCV_CPU_DISABLE" in would_pin:
        late.append("cv2")
    return tuple(late)


def pin_all() -> tuple[str, ...]:
    """Every pin above, the CPU's flags read once; the modules `loaded_too_late` names, judged
    before any pin set a variable (what `import uma` calls, and warns about)."""
    flags = cpu_flags(cpuinfo_text())
    late = loaded_too_late(os.environ, flags, frozenset(sys.modules))
    pin_kernels(flags)
    pin_blas_threads()
    pin_dispatch(flags)
    pin_opencv_threads()
    return late
