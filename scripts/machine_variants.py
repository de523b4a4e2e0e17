"""Run scenarios as other machines would, and say whether every result file is the same.

    python scripts/machine_variants.py [--out DIR] SCENARIO.yaml...

A seed reproduces a run byte for byte on one machine; this checks the machines this one can
pretend to be. Each scenario is run with `uma run` (this checkout, in a fresh process) under
each variant of the libraries' CPU choices that uma does not pin: numba's target CPU
(`NUMBA_CPU_NAME=generic`: SSE2 only, a cache of its own) and NumPy's dispatched SIMD
(`NPY_DISABLE_CPU_FEATURES`). OpenBLAS's kernel set is pinned at `import uma` (`uma.blas`), so
it is not varied. It prints, per scenario and variant, `same` or the first line of
`frames.csv` / `events.csv` / `metrics.json` that differs from the native run's, and exits 1 if
any differs. An AVX-512 machine cannot be pretended to here (docs/experiments.md).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FILES = ("frames.csv", "events.csv", "metrics.json")
VARIANTS: dict[str, dict[str, str]] = {
    "native": {},
    "numba-generic": {"NUMBA_CPU_NAME": "generic"},
    "numpy-no-x86-v3": {"NPY_DISABLE_CPU_FEATURES": "X86_V3"},
}


def _run(scenario: Path, out: Path, env: dict[str, str], cache: Path) -> None:
    full = dict(os.environ, PYTHONPATH=str(ROOT), NUMBA_CACHE_DIR=str(cache), **env)
    done = subprocess.run(
        [sys.executable, "-m", "uma", "run", str(scenario), "--out", str(out), "--quiet"],
        env=full,
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        raise SystemExit(f"{scenario}: uma run failed under {env}: {done.stderr.strip()}")


def _first_difference(a: Path, b: Path) -> str | None:
    for name in FILES:
        left, right = (a / name).read_text().splitlines(), (b / name).read_text().splitlines()
        for number, (x, y) in enumerate(zip(left, right, strict=False), start=1):
            if x != y:
                return f"{name} line {number}: {x[:90]!r} != {y[:90]!r}"
        if len(left) != len(right):
            return f"{name}: {len(left)} lines against {len(right)}"
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenarios", nargs="+", type=Path)
    parser.add_argument("--out", type=Path, default=None, help="keep the runs here")
    args = parser.parse_args(argv)
    base = args.out or Path(tempfile.mkdtemp(prefix="uma-variants-"))
    differs = 0
    for scenario in args.scenarios:
        for name, env in VARIANTS.items():
            cache = base / "numba-cache" / ("generic" if "NUMBA_CPU_NAME" in env else "native")
            _run(scenario, base / scenario.stem / name, env, cache)
            found = _first_difference(base / scenario.stem / "native", base / scenario.stem / name)
            differs += found is not None
            print(f"{scenario.stem} {name}: {found or 'same'}", flush=True)
    return 1 if differs else 0


if __name__ == "__main__":
    sys.exit(main())
