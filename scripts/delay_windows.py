"""Where in a run the display delay's tail lies: display instants over a delay, per window.

    python scripts/delay_windows.py RUN_DIR [RUN_DIR ...] [--over-ms 3000] [--window-s 10]
        [--detail FROM_S:TO_S]

reads each `uma run` results folder's `frames.csv` (one row a display instant; the runs must
have the same instants, e.g. one scenario with `--set engine.policy=oracle` beside the
default) and prints, per window of capture time holding any, how many instants each run
showed older than `--over-ms` (the part of the run its delay p95 comes from) and the link's
mean capacity there; then the totals. With `--detail`, per second of that stretch, each run's
mean estimate, bottleneck queue, display delay, frozen share and bits coded, beside the
capacity: what the sender did while the tail was made.
"""

from __future__ import annotations

import argparse
import csv
import sys
from collections import defaultdict
from pathlib import Path

__all__ = ["load", "over_by_window", "main"]


def _fail(message: str) -> None:
    """Bad input: one line on stderr, exit 2."""
    print(f"uma: error: {message}", file=sys.stderr)
    raise SystemExit(2)


def load(run: Path) -> list[dict[str, str]]:
    """The rows of `run`/frames.csv; exit 2 naming the file when it is absent or not one."""
    path = run / "frames.csv"
    try:
        with path.open(newline="") as handle:
            rows = list(csv.DictReader(handle))
    except OSError as error:
        _fail(f"{path}: cannot read ({error.strerror})")
    needed = ("capture_ms", "delay_ms", "capacity_kbps", "frozen", "size_bits")
    if not rows or not set(needed) <= set(rows[0]):
        _fail(f"{path}: expected a uma run's frames.csv with {list(needed)}")
    for line, row in enumerate(rows, start=2):
        try:
            for key in needed:
                float(row[key] or 0.0)
        except (TypeError, ValueError):
            _fail(f"{path}:{line}: {key}: expected a number, got {row[key]!r}")
    return rows


def over_by_window(rows, over_ms: float, window_s: float) -> dict[int, int]:
    """Window index -> instants whose display delay exceeds `over_ms`."""
    counts: dict[int, int] = defaultdict(int)
    for row in rows:
        if float(row["delay_ms"]) > over_ms:
            counts[int(float(row["capture_ms"]) / 1000.0 // window_s)] += 1
    return counts


def _mean(rows, key: str) -> float:
    return sum(float(r[key] or 0.0) for r in rows) / len(rows)


def _windows(runs: dict[str, list], over_ms: float, window_s: float) -> None:
    counts = {name: over_by_window(rows, over_ms, window_s) for name, rows in runs.items()}
    first = next(iter(runs.values()))
    capacity: dict[int, list] = defaultdict(list)
    for row in first:
        capacity[int(float(row["capture_ms"]) / 1000.0 // window_s)].append(row)
    names = list(runs)
    print(f"window (s) | {' | '.join(names)} | capacity kbit/s  (instants over {over_ms:g} ms)")
    for index in sorted(set().union(*counts.values())):
        cells = " | ".join(str(counts[n].get(index, 0)) for n in names)
        cap = _mean(capacity[index], "capacity_kbps")
        print(f"{index * window_s:g}-{(index + 1) * window_s:g} | {cells} | {cap:.0f}")
    totals = " | ".join(str(sum(counts[n].values())) for n in names)
    print(f"all | {totals} | of {len(first)} instants")


def _detail(runs: dict[str, list], from_s: float, to_s: float) -> None:
    names = list(runs)
    per_second: dict[str, dict[int, list]] = {n: defaultdict(list) for n in names}
    for name, rows in runs.items():
        for row in rows:
            second = int(float(row["capture_ms"]) // 1000)
            if from_s <= second < to_s:
                per_second[name][second].append(row)
    head = " | ".join(f"{n}: estimate, queue B, delay ms, frozen, kbit" for n in names)
    print(f"\nsecond | capacity kbit/s | {head}")
    for second in sorted(per_second[names[0]]):
        cells = []
        for name in names:
            rows = per_second[name][second]
            cells.append(
                f"{_mean(rows, 'estimate_kbps'):.0f}, {_mean(rows, 'queue_bytes'):.0f}, "
                f"{_mean(rows, 'delay_ms'):.0f}, {_mean(rows, 'frozen'):.2f}, "
                f"{sum(float(r['size_bits'] or 0) for r in rows) / 1000:.0f}"
            )
        capacity = _mean(per_second[names[0]][second], "capacity_kbps")
        print(f"{second} | {capacity:.0f} | {' | '.join(cells)}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path, help="uma run results folders")
    parser.add_argument("--over-ms", type=float, default=3000.0)
    parser.add_argument("--window-s", type=float, default=10.0)
    parser.add_argument("--detail", help="FROM_S:TO_S, per second")
    args = parser.parse_args(argv)
    runs = {str(run): load(run) for run in args.runs}
    lengths = {len(rows) for rows in runs.values()}
    if len(lengths) != 1:
        _fail("the runs have different numbers of display instants")
    _windows(runs, args.over_ms, args.window_s)
    if args.detail:
        try:
            from_s, to_s = (float(v) for v in args.detail.split(":"))
        except ValueError:
            _fail(f"--detail {args.detail!r}: expected FROM_S:TO_S in seconds")
        _detail(runs, from_s, to_s)


if __name__ == "__main__":
    main()
