"""`import uma` pins OpenBLAS's kernel set where the CPU can run it, keeps OpenCV and NumPy off
their AVX-512 paths, and OpenBLAS and OpenCV to one thread each, unless the user chose."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

import uma.experiments.machine
from uma.blas import (
    PINNED_BLAS_THREADS,
    PINNED_CORE,
    PINNED_DISPATCH,
    PINNED_OPENCV_THREADS,
    cpu_flags,
    loaded_too_late,
    pinned_blas_threads,
    pinned_core,
    pinned_dispatch,
    pinned_opencv_threads,
)

_AVX2 = frozenset({"sse2", "avx", "avx2", "fma"})


def test_an_avx2_cpu_is_pinned_to_the_haswell_kernels():
    assert pinned_core({}, _AVX2, numpy_loaded=False) == PINNED_CORE == "Haswell"
    assert pinned_core({}, _AVX2 | {"avx512f"}, numpy_loaded=False) == "Haswell"


@pytest.mark.parametrize(
    ("environ", "flags", "numpy_loaded"),
    [
        ({"OPENBLAS_CORETYPE": "Prescott"}, _AVX2, False),  # the user's (or a check's) choice
        ({}, _AVX2, True),  # NumPy loaded first: OpenBLAS has chosen already
        ({}, frozenset({"sse2", "avx"}), False),  # no AVX2: those kernels would not run
        ({}, frozenset({"avx2"}), False),  # no FMA
        ({}, frozenset(), False),  # no /proc/cpuinfo (another OS)
    ],
    ids=["user-set", "numpy-first", "no-avx2", "no-fma", "unknown-cpu"],
)
def test_otherwise_openblas_keeps_its_own_choice(environ, flags, numpy_loaded):
    assert pinned_core(environ, flags, numpy_loaded) is None


def test_one_blas_thread_unless_the_user_chose_a_count():
    assert pinned_blas_threads({}, numpy_loaded=False) == PINNED_BLAS_THREADS == 1
    for name in ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"):
        assert pinned_blas_threads({name: "4"}, numpy_loaded=False) is None
    assert pinned_blas_threads({}, numpy_loaded=True) is None  # OpenBLAS has started its threads


_PINNED_BY_UMA = (
    "OPENCV_CPU_DISABLE",
    "NPY_DISABLE_CPU_FEATURES",
    "OPENBLAS_CORETYPE",
    "OPENBLAS_NUM_THREADS",
    "GOTO_NUM_THREADS",
    "OMP_NUM_THREADS",
)


def _in_a_process(code: str, **env: str) -> str:
    clean = {k: v for k, v in os.environ.items() if k not in _PINNED_BY_UMA}
    done = subprocess.run(
        [sys.executable, "-c", code], env={**clean, **env}, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


# machine.py alone, by its path: `uma.experiments` would load the simulation (1.5 s a process).
_MACHINE_PY = Path(uma.experiments.machine.__file__)
_REPORT = (
    "import os, importlib.util as u\n"
    f"s = u.spec_from_file_location('machine', {str(_MACHINE_PY)!r})\n"
    "m = u.module_from_spec(s); s.loader.exec_module(m)\n"
    "print(os.environ.get('OPENBLAS_CORETYPE'), m.blas_core())"
)


def test_importing_uma_first_runs_numpy_on_the_pinned_kernels():
    with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as stream:
        if not cpu_flags(stream.read()) >= {"avx2", "fma"}:
            pytest.skip("this CPU cannot run the Haswell kernels")
    told, ran = _in_a_process("import uma\n" + _REPORT).split()
    if ran == "None":
        pytest.skip("this NumPy has no OpenBLAS")
    assert told == ran == "Haswell"
    assert _in_a_process("import uma\n" + _REPORT, OPENBLAS_CORETYPE="Prescott").split()[1] not in (
        "Haswell",
        "None",
    )


_THREADS = _REPORT.replace("'OPENBLAS_CORETYPE'", "'OPENBLAS_NUM_THREADS'").replace(
    "m.blas_core()", "m.blas_threads()"
)


def test_importing_uma_first_runs_numpy_on_one_blas_thread():
    told, ran = _in_a_process("import uma\n" + _THREADS).split()
    if ran == "None":
        pytest.skip("this NumPy has no OpenBLAS")
    assert told == ran == "1"
    assert _in_a_process("import uma\n" + _THREADS, OPENBLAS_NUM_THREADS="2").split() == ["2", "2"]
    assert _in_a_process("import uma\n" + _THREADS, OMP_NUM_THREADS="2").split()[1] == "2"


def test_opencv_runs_one_thread_unless_told_or_loaded_first():
    assert pinned_opencv_threads({}, opencv_loaded=False) == PINNED_OPENCV_THREADS == 1
    assert pinned_opencv_threads({"OPENCV_FOR_THREADS_NUM": "3"}, opencv_loaded=False) is None
    assert pinned_opencv_threads({}, opencv_loaded=True) is None


def _opencv_threads_in_a_process(first: str, **env: str) -> int:
    clean = {k: v for k, v in os.environ.items() if k != "OPENCV_FOR_THREADS_NUM"}
    code = f"import {first}\nimport cv2, uma\nprint(cv2.getNumThreads())"
    done = subprocess.run(
        [sys.executable, "-c", code], env={**clean, **env}, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    return int(done.stdout)


def test_importing_uma_first_runs_opencv_on_one_thread():
    if os.cpu_count() == 1:
        pytest.skip("one core: OpenCV's default is one thread already")
    assert _opencv_threads_in_a_process("uma") == 1
    assert _opencv_threads_in_a_process("uma", OPENCV_FOR_THREADS_NUM="3") == 3
    assert _opencv_threads_in_a_process("cv2") > 1  # loaded first: its own pool


_AVX512 = _AVX2 | {"avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl"}


def test_an_avx512_cpu_keeps_opencv_and_numpy_off_their_avx512_paths():
    assert pinned_dispatch({}, _AVX512, frozenset()) == {
        "OPENCV_CPU_DISABLE": "AVX512-SKX",
        "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR",
    }
    # No AVX-512 (or only part of it): nothing to keep off, and OpenCV would print a line
    # about a feature this CPU does not have.
    assert pinned_dispatch({}, _AVX2, frozenset()) == {}
    assert pinned_dispatch({}, _AVX2 | {"avx512f"}, frozenset()) == {}
    # The user's choice, or a library loaded before uma, is left alone.
    assert pinned_dispatch({"OPENCV_CPU_DISABLE": ""}, _AVX512, frozenset()) == {
        "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR"
    }
    assert pinned_dispatch({}, _AVX512, frozenset({"numpy", "cv2"})) == {}


_DISPATCH = (
    "import uma, cv2, numpy, os\n"
    "print([os.environ.get(v) for v, _, _ in uma.blas.PINNED_DISPATCH], cv2.getCPUFeaturesLine())"
)


def test_importing_uma_then_opencv_and_numpy_prints_nothing_and_pins_by_the_cpu():
    clean = {k: v for k, v in os.environ.items() if k not in _PINNED_BY_UMA}
    done = subprocess.run(
        [sys.executable, "-c", _DISPATCH], env=clean, capture_output=True, text=True
    )
    assert done.returncode == 0 and done.stderr == "", done.stderr
    with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as stream:
        avx512 = cpu_flags(stream.read()) >= _AVX512 - _AVX2
    told = [value for _, value, _ in PINNED_DISPATCH] if avx512 else [None, None]
    assert done.stdout.startswith(repr(told))
    if avx512:  # OpenCV marks a dispatched feature it was told not to use with "?"
        assert "AVX512-SKX?" in done.stdout


def test_a_library_loaded_before_uma_that_a_pin_would_reach_is_named():
    assert loaded_too_late({}, _AVX512, frozenset({"numpy", "cv2"})) == ("numpy", "cv2")
    assert loaded_too_late({}, _AVX2, frozenset({"numpy", "cv2"})) == ("numpy",)  # threads
    assert loaded_too_late({}, _AVX512, frozenset()) == ()
    # Every variable already chosen (the user's, or a parent uma process's): nothing missed.
    chosen = {variable: value for variable, value, _ in PINNED_DISPATCH}
    chosen |= {"OPENBLAS_CORETYPE": "Haswell", "OPENBLAS_NUM_THREADS": "1"}
    assert loaded_too_late(chosen, _AVX512, frozenset({"numpy", "cv2"})) == ()


def _warnings_of(code: str) -> str:
    clean = {k: v for k, v in os.environ.items() if k not in _PINNED_BY_UMA}
    done = subprocess.run(
        [sys.executable, "-W", "always", "-c", code], env=clean, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    return done.stderr


def test_importing_numpy_before_uma_warns_and_uma_first_does_not():
    assert "numpy imported before uma" in _warnings_of("import numpy\nimport uma")
    assert _warnings_of("import uma\nimport numpy") == ""


_HEAVY = {"numpy", "cv2", "pandas", "scipy", "av"}


def _first_line(tree, wanted) -> int | None:
    lines = [
        node.lineno
        for node in ast.walk(tree)
        if isinstance(node, ast.Import | ast.ImportFrom) and wanted(node)
    ]
    return min(lines, default=None)


def _names(node) -> set[str]:
    if isinstance(node, ast.ImportFrom):
        return {(node.module or "").split(".")[0]}
    return {alias.name.split(".")[0] for alias in node.names}


_SCRIPTS = sorted((Path(__file__).resolve().parents[1] / "scripts").glob("*.py"))


def test_the_scripts_are_found():
    assert len(_SCRIPTS) >= 20  # from any working folder, so the check below is never empty


@pytest.mark.parametrize("script", _SCRIPTS, ids=lambda p: p.stem)
def test_a_script_imports_uma_before_numpy_or_opencv(script):
    """A script that loaded NumPy first ran the links bench's case with other figures than
    the bench's on the AVX-512 machine (scripts/delay_tail.py, docs/measured.md section 21)."""
    tree = ast.parse(script.read_text(encoding="utf-8"))
    heavy = _first_line(tree, lambda node: _names(node) & _HEAVY)
    if heavy is None:
        return
    first_uma = _first_line(tree, lambda node: "uma" in _names(node))
    assert first_uma is not None and first_uma < heavy, f"{script}: uma after line {heavy}"
