"""Run one `uma bench` with --json and record its output in docs/results/ with its provenance.

    python scripts/record_bench.py [--variant V] [--allow-dirty] NAME [bench args...]

runs `python -m uma bench NAME --json [bench args...]` from the repository root (the uma package
of this checkout) and writes `docs/results/NAME.json` (`NAME-V.json` with --variant) holding
`result` (the bench's JSON object, unchanged) beside `command` (what a user types), `argv`,
`commit`, `dirty`, `date_utc`, `load_1m` (before and after), `cores`, `duration_s` and
`machine` (its class, CPU and library versions: a seed's figures belong to a kind of machine
too, `uma.experiments.machine`).
The file is written atomically (temporary file, then rename) and only when the bench exits 0
and printed one JSON object. A dirty tree (uncommitted changes) is refused unless
--allow-dirty, which is then recorded. Exit 0 recorded; 1 the bench failed; 2 bad input.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["main", "record", "record_doc", "result_path", "run_bench", "tree"]

ROOT = Path(__file__).resolve().parent.parent
RESULTS_DIR = ROOT / "docs" / "results"
_NAME = re.compile(r"^[a-z][a-z0-9-]*$")


class RecordError(ValueError):
    """Bad input to the recorder (exit 2)."""


def _git(*args: str) -> str:
    done = subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise RecordError(f"git {' '.join(args)} failed in {ROOT}: {done.stderr.strip()}")
    return done.stdout.strip()


def result_path(name: str, variant: str | None, results_dir: Path = RESULTS_DIR) -> Path:
    """The file a bench's record goes to: NAME.json, or NAME-VARIANT.json."""
    for label, value in (("bench name", name), ("--variant", variant)):
        if value is not None and not _NAME.match(value):
            raise RecordError(
                f"{label}: expected lower-case letters, digits and '-', got {value!r}"
            )
    return results_dir / (f"{name}-{variant}.json" if variant else f"{name}.json")


def _write_atomic(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as out:
            out.write(text)
            out.flush()
            os.fsync(out.fileno())
        os.chmod(tmp, 0o644)  # mkstemp makes it 0600; a record is for everyone to read
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _machine() -> dict:
    """`uma.experiments.machine.machine_summary()` of this checkout's uma."""
    sys.path.insert(0, str(ROOT))
    try:
        from uma.experiments.machine import machine_summary
    finally:
        sys.path.pop(0)
    return machine_summary()


def tree(allow_dirty: bool) -> tuple[str, bool]:
    """This checkout's commit and whether it has uncommitted changes; RecordError when it has
    and `allow_dirty` is not given."""
    commit = _git("rev-parse", "HEAD")
    dirty = bool(_git("status", "--porcelain", "--untracked-files=no"))
    if dirty and not allow_dirty:
        raise RecordError(
            f"{ROOT}: uncommitted changes; commit them first (or pass --allow-dirty, recorded)"
        )
    return commit, dirty


def record_doc(command: str, argv: list[str], tree: tuple[str, bool], load_before: float,
               duration_s: float, result: dict) -> dict:  # fmt: skip
    """A record: `result` beside what ran (`command` as a user types it, `argv`), the tree
    (commit, dirty), the load before and now, the wall time and the machine."""
    return {
        "command": command,
        "argv": argv[1:],
        "commit": tree[0],
        "dirty": tree[1],
        "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "load_1m": {"before": round(load_before, 2), "after": round(os.getloadavg()[0], 2)},
        "cores": os.cpu_count(),
        "duration_s": round(duration_s, 1),
        "machine": _machine(),
        "result": result,
    }


def run_bench(name: str, argv: list[str]) -> dict:
    """`argv` (a `uma bench NAME ... --json`) run from the repository root with this checkout's
    uma; the JSON object it printed, or RuntimeError."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    done = subprocess.run(argv, cwd=ROOT, env=env, stdout=subprocess.PIPE, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"uma bench {name} exited {done.returncode}; nothing recorded")
    try:
        result = json.loads(done.stdout)
    except ValueError as exc:
        raise RuntimeError(f"uma bench {name} --json printed no JSON object: {exc}") from exc
    if not isinstance(result, dict):
        raise RuntimeError(f"uma bench {name} --json printed a {type(result).__name__}")
    return result


def record(
    name: str, bench_args: list[str], variant: str | None = None, allow_dirty: bool = False
) -> Path:
    """Run the bench, then write and return its record; raise RecordError or RuntimeError."""
    path = result_path(name, variant)
    if "--json" in bench_args:
        bench_args = [a for a in bench_args if a != "--json"]
    commit, dirty = tree(allow_dirty)
    argv = [sys.executable, "-m", "uma", "bench", name, *bench_args, "--json"]
    load_before = os.getloadavg()[0]
    start = time.monotonic()
    result = run_bench(name, argv)
    duration_s = time.monotonic() - start
    command = " ".join(["uma", "bench", name, *bench_args, "--json"])
    doc = record_doc(command, argv, (commit, dirty), load_before, duration_s, result)
    _write_atomic(path, json.dumps(doc, indent=2, sort_keys=False) + "\n")
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="record_bench.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--variant", help="record as NAME-VARIANT.json")
    parser.add_argument("--allow-dirty", action="store_true", help="record from a dirty tree")
    parser.add_argument("name", help="the bench: headline, salsify, mbc, sim, init, ...")
    parser.add_argument("bench_args", nargs=argparse.REMAINDER, help="passed to the bench")
    args = parser.parse_args(argv)
    try:
        path = record(args.name, args.bench_args, args.variant, args.allow_dirty)
    except RecordError as exc:
        print(f"record_bench: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:
        print(f"record_bench: error: {exc}", file=sys.stderr)
        return 1
    print(path.relative_to(ROOT))
    return 0


if __name__ == "__main__":
    sys.exit(main())
