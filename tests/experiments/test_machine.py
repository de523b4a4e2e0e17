"""The machine class that picks a regression baseline, and what a record says of its machine."""

from __future__ import annotations

import pytest

import uma.experiments.machine
from uma.errors import ConfigError
from uma.experiments.machine import cpu_flags, machine_class, machine_summary
from uma.experiments.regress import load_suite

_AVX512 = "processor\t: 0\nmodel name\t: AMD EPYC\nflags\t\t: fpu sse2 avx avx2 avx512f avx512bw\n"
_MACHINE_PY = uma.experiments.machine.__file__
_AVX2 = "processor\t: 0\nmodel name\t: AMD EPYC\nflags\t\t: fpu sse2 avx avx2\n"


def test_cpu_flags_read_the_first_processors_flags_line():
    assert cpu_flags(_AVX512) == {"fpu", "sse2", "avx", "avx2", "avx512f", "avx512bw"}
    assert cpu_flags("model name : x\n") == frozenset()


@pytest.mark.parametrize(("text", "expected"), [(_AVX512, "avx512"), (_AVX2, "default")])
def test_the_class_is_avx512_only_with_avx512f(tmp_path, text, expected):
    (tmp_path / "cpuinfo").write_text(text)
    assert machine_class(tmp_path / "cpuinfo") == expected
    summary = machine_summary(tmp_path / "cpuinfo")
    assert summary["class"] == expected and summary["cpu"] == "AMD EPYC"
    assert summary["packages"]["numpy"]  # installed, so it has a version


def _core_under(coretype: str) -> str:
    import os
    import subprocess
    import sys

    # The module alone, by its path: `uma.experiments` loads the simulation (1.5 s a process).
    code = (
        "import importlib.util as u\n"
        f"s = u.spec_from_file_location('machine', {str(_MACHINE_PY)!r})\n"
        "m = u.module_from_spec(s); s.loader.exec_module(m); print(m.blas_core())"
    )
    env = {**os.environ, "OPENBLAS_CORETYPE": coretype}
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    return done.stdout.strip()


def test_the_blas_core_follows_what_openblas_was_told_to_run():
    haswell, old = _core_under("Haswell"), _core_under("Prescott")
    if "None" in (haswell, old):
        pytest.skip("this NumPy has no OpenBLAS")
    assert haswell == "Haswell" and old not in ("", "Haswell")


def test_a_machine_that_cannot_be_read_is_default(tmp_path):
    assert machine_class(tmp_path / "absent") == "default"


def _suite(tmp_path, extra: str = "") -> None:
    (tmp_path / "suite.yaml").write_text(
        "baseline: b.yaml\n" + extra + "scenarios: [a.yaml]\nmetrics:\n"
        "  psnr_db: {worse: down, absolute: 0.3}\n"
    )


def test_a_suite_picks_the_machines_own_baseline_and_the_default_for_others(tmp_path):
    _suite(tmp_path, "machine_baselines: {avx512: b-avx512.yaml}\n")
    assert load_suite(tmp_path / "suite.yaml", "avx512").baseline_path.name == "b-avx512.yaml"
    own = load_suite(tmp_path / "suite.yaml", "default")
    assert own.baseline_path.name == "b.yaml" and own.machine == "default"
    _suite(tmp_path)
    assert load_suite(tmp_path / "suite.yaml", "avx512").baseline_path.name == "b.yaml"


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ("machine_baselines: {arm: b-arm.yaml}\n", "unknown machine class 'arm'"),
        ("machine_baselines: {default: x.yaml}\n", "unknown machine class 'default'"),
        ("machine_baselines: [b.yaml]\n", "expected a mapping of machine class"),
        ("machine_baselines: {avx512: 3}\n", "expected the baseline file's path"),
    ],
)
def test_a_bad_machine_baselines_key_is_one_line_naming_it(tmp_path, extra, message):
    _suite(tmp_path, extra)
    with pytest.raises(ConfigError, match=message) as err:
        load_suite(tmp_path / "suite.yaml")
    assert "suite.yaml:2 (machine_baselines" in str(err.value)
