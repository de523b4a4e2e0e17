"""`scripts/delay_windows.py`: which windows of a run hold its display-delay tail, counted
against hand-made `frames.csv` files, and its bad-input lines."""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import delay_windows  # noqa: E402

FIELDS = ("capture_ms", "delay_ms", "capacity_kbps", "frozen", "size_bits", "estimate_kbps",
          "queue_bytes")  # fmt: skip


def _run(folder: Path, delays_ms: list[float]) -> Path:
    """A run of one instant every 40 ms with these display delays."""
    folder.mkdir()
    with (folder / "frames.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, FIELDS)
        writer.writeheader()
        for index, delay in enumerate(delays_ms):
            writer.writerow({"capture_ms": 40 * index, "delay_ms": delay, "capacity_kbps": 100,
                             "frozen": int(delay > 1000), "size_bits": 800,
                             "estimate_kbps": 90, "queue_bytes": 0})  # fmt: skip
    return folder


def test_instants_over_the_delay_are_counted_in_their_window(tmp_path):
    # 250 instants (10 s): 5 over 3 s at 2-3 s, 3 at 12-13 s (window 1 at 10 s windows).
    delays = [100.0] * 500
    delays[50:55] = [3500.0] * 5
    delays[300:303] = [4000.0] * 3
    delays[310] = 3000.0  # not over: the count is of delays above the limit
    rows = delay_windows.load(_run(tmp_path / "a", delays))
    assert dict(delay_windows.over_by_window(rows, 3000.0, 10.0)) == {0: 5, 1: 3}
    assert dict(delay_windows.over_by_window(rows, 3000.0, 1.0)) == {2: 5, 12: 3}


def test_two_runs_side_by_side_and_the_detail(tmp_path, capsys):
    a = _run(tmp_path / "a", [100.0] * 20 + [5000.0] * 30)
    b = _run(tmp_path / "b", [100.0] * 50)
    delay_windows.main([str(a), str(b), "--window-s", "1", "--detail", "0:2"])
    out = capsys.readouterr().out
    assert "0-1 | 5 | 0 | 100" in out and "1-2 | 25 | 0 | 100" in out
    assert "all | 30 | 0 | of 50 instants" in out
    assert "\n1 | 100 | 90, 0, 5000, 1.00, 20 | 90, 0, 100, 0.00, 20" in out


@pytest.mark.parametrize(
    ("make", "says"),
    [
        (lambda d: d / "none", "none/frames.csv: cannot read"),
        (lambda d: _bad(d, "capture_ms\n1\n"), "expected a uma run's frames.csv with"),
        (lambda d: _bad(d, ",".join(FIELDS[:5]) + "\n0,x,1,0,1\n"), "frames.csv:2: delay_ms: "),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, make, says):
    with pytest.raises(SystemExit) as stop:
        delay_windows.main([str(make(tmp_path))])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert says in err and err.count("\n") == 1


def _bad(folder: Path, text: str) -> Path:
    run = folder / "bad"
    run.mkdir()
    (run / "frames.csv").write_text(text)
    return run
