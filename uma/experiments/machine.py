"""Which kind of machine a run's figures belong to: the regression gate's baselines, the records.

A seed reproduces a run byte for byte on one machine. From one machine to another, the same
commit gave other figures on a 2-core AMD EPYC with AVX-512 than on one without it
(`docs/experiments.md`): OpenBLAS's kernel set (`blas_core` names it; `import uma` now pins
it, `uma.blas`) and the fitting kernels' `fastmath` (now off) each moved a run as far, and
OpenBLAS's thread count moved a description's fit (`blas_threads`; pinned to one too). On an
AVX-512 machine OpenCV's and NumPy's AVX-512 paths moved the pattern's pixels and the model
codec's figures (`import uma` keeps them off those paths, `uma.blas.pin_dispatch`; `avx512_off`
says what was kept off). The gate keeps one baseline; a suite may still name a baseline per
class (`machine_baselines`) if a kind of machine is ever shown to differ. The class is named by the CPU feature that told the
two apart. Reads `/proc/cpuinfo` where there is one; elsewhere the class is `default`.
"""

from __future__ import annotations

import os
import platform
from importlib import metadata
from pathlib import Path

from uma.blas import PINNED_DISPATCH, cpu_flags, cpuinfo_text
from uma.errors import ConfigError

__all__ = [
    "MACHINE_CLASSES",
    "blas_core",
    "blas_threads",
    "cpu_flags",
    "machine_baselines",
    "machine_class",
    "machine_summary",
]

# The classes a suite may key a baseline by: `avx512` (the CPU has AVX-512F), `default` (any
# other machine, and machines whose CPU cannot be read).
MACHINE_CLASSES = ("avx512", "default")

# The libraries whose versions move a run's figures (pixels, bits, floating-point paths).
_PACKAGES = ("numpy", "scipy", "numba", "opencv-python-headless", "av", "scikit-image")

_CPUINFO = Path("/proc/cpuinfo")


def machine_class(cpuinfo_path: Path = _CPUINFO) -> str:
    """`avx512` when the CPU has AVX-512F, else `default` (one of `MACHINE_CLASSES`)."""
    return "avx512" if "avx512f" in cpu_flags(cpuinfo_text(cpuinfo_path)) else "default"


def _cpu_model(cpuinfo_text: str) -> str:
    for line in cpuinfo_text.splitlines():
        key, sep, value = line.partition(":")
        if sep and key.strip() == "model name":
            return value.strip()
    return platform.processor() or platform.machine()


def _version(package: str) -> str | None:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return None


def _openblas_call(names: tuple[str, ...], restype: type) -> object | None:
    """Call the first of `names` that NumPy's OpenBLAS exports (no arguments), or None."""
    import ctypes

    import numpy

    folder = Path(numpy.__file__).parent.parent / "numpy.libs"
    for library in sorted(folder.glob("*openblas*")):
        try:
            lib = ctypes.CDLL(str(library))
        except OSError:
            continue
        for name in names:
            call = getattr(lib, name, None)
            if call is not None:
                call.restype = restype
                return call()
    return None


def blas_core() -> str | None:
    """The kernel set NumPy's OpenBLAS runs on this CPU (`Haswell`, `SkylakeX`, ...), or None.

    OpenBLAS picks it at load time from the CPU (`OPENBLAS_CORETYPE` overrides it), and the
    figures of a run depend on it (docs/experiments.md)."""
    import ctypes

    names = ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename")
    core = _openblas_call(names, ctypes.c_char_p)
    return None if core is None else core.decode("ascii", "replace")


def blas_threads() -> int | None:
    """The thread count NumPy's OpenBLAS runs with (`import uma` pins 1), or None.

    A factorisation's last bits depend on it (one thread against several, docs/experiments.md)."""
    import ctypes

    names = ("scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads")
    return _openblas_call(names, ctypes.c_int)


def machine_summary(cpuinfo_path: Path = _CPUINFO) -> dict:
    """What a record says of the machine that made it: class, CPU, BLAS kernels and threads,
    the AVX-512 paths kept off, Python, library versions."""
    text = cpuinfo_text(cpuinfo_path)
    return {
        "class": "avx512" if "avx512f" in cpu_flags(text) else "default",
        "cpu": _cpu_model(text),
        "blas_core": blas_core(),
        "blas_threads": blas_threads(),
        "avx512_off": {v: os.environ[v] for v, _, _ in PINNED_DISPATCH if v in os.environ},
        "arch": platform.machine(),
        "python": platform.python_version(),
        "packages": {name: _version(name) for name in _PACKAGES},
    }


def machine_baselines(data: object, where: str) -> dict[str, str]:
    """The suite's `machine_baselines` (machine class -> baseline file), checked."""
    if data is None:
        return {}
    if not isinstance(data, dict) or not data:
        raise ConfigError(f"{where}: expected a mapping of machine class -> baseline file")
    for name, file in data.items():
        if name not in MACHINE_CLASSES or name == "default":
            raise ConfigError(
                f"{where}: unknown machine class {name!r}, expected one of "
                f"{', '.join(c for c in MACHINE_CLASSES if c != 'default')} "
                f"(`baseline` serves every other machine)"
            )
        if not isinstance(file, str) or not file:
            raise ConfigError(f"{where} ({name}): expected the baseline file's path, got {file!r}")
    return {str(name): file for name, file in data.items()}
