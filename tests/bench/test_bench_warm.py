"""`python -m uma.bench.warm` (run by `make install`) leaves every kernel the default scenario
calls in numba's cache, so a later process loads them instead of compiling."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

# The warm-up again in a fresh process, then numba's own count of what it compiled (cache
# misses) and loaded (cache hits), summed over the project's kernels.
AGAIN = textwrap.dedent(
    """
    import importlib, json
    from uma.bench.timing import KERNEL_MODULES
    from uma.bench.warm import warm_default_kernels

    warm_default_kernels()
    misses, hits = [], 0
    for name in KERNEL_MODULES:
        for attr, value in vars(importlib.import_module(name)).items():
            stats = getattr(value, "stats", None)
            if stats is not None and hasattr(value, "py_func"):
                misses += [f"{name}.{attr}"] * sum(stats.cache_misses.values())
                hits += sum(stats.cache_hits.values())
    print(json.dumps({"misses": misses, "hits": hits}))
    """
)


@pytest.mark.slow
def test_after_the_warm_up_a_process_compiles_no_kernel(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    first = subprocess.run([sys.executable, "-m", "uma.bench.warm"], env=env, cwd=ROOT,
                           capture_output=True, text=True, timeout=600)  # fmt: skip
    assert first.returncode == 0, first.stderr
    assert "numba kernels compiled or loaded in" in first.stderr
    again = subprocess.run([sys.executable, "-c", AGAIN], env=env, cwd=ROOT,
                           capture_output=True, text=True, timeout=600)  # fmt: skip
    assert again.returncode == 0, again.stderr
    counts = json.loads(again.stdout.strip().splitlines()[-1])
    assert counts["misses"] == [] and counts["hits"] >= 15, counts
