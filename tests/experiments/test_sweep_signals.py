"""Issue 28, item 9: `uma sweep` interrupted by SIGINT or SIGTERM, at start-up or mid-run, to
the process or its whole group (Ctrl-C in a terminal): one line, exit 130 or 143, never a
`concurrent.futures` traceback."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
BASE = """\
name: base
seed: 1
source: {kind: pattern, width: 96, height: 64, fps: 25}
route:
  - {technology: 3G, duration_s: 4.0}
"""
# Long enough (12 points of 4 s) that "mid-run" is mid-run on a fast, idle machine too; every
# case interrupts it within about a second, so its length costs no test time.
EXPERIMENT = "name: grid\nbase: base.yaml\ngrid:\n  seed: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]\n"


def interrupt(tmp_path: Path, number: int, *, group: bool, when: str) -> tuple[int, str]:
    """Interrupt a sweep; again, later, if the signal landed before uma ran a line.

    Under load a signal 0.3 s after the start can land in the interpreter's own `site` import
    (`Fatal Python error: init_import_site`, a traceback through `site.py`), before any of
    uma's code: nothing uma can catch, so that attempt says nothing about uma.
    """
    for delay_s in (0.3, 0.6, 1.2):
        code, err = _interrupt_once(tmp_path, number, group=group, when=when, delay_s=delay_s)
        if "init_import_site" not in err:
            break
    return code, err


def _interrupt_once(
    tmp_path: Path, number: int, *, group: bool, when: str, delay_s: float
) -> tuple[int, str]:
    (tmp_path / "base.yaml").write_text(BASE)
    (tmp_path / "exp.yaml").write_text(EXPERIMENT)
    out = tmp_path / "out"
    shutil.rmtree(out, ignore_errors=True)
    process = subprocess.Popen(
        [sys.executable, "-m", "uma", "sweep", "exp.yaml", "--out", str(out), "--quiet"],
        cwd=tmp_path,
        env=dict(os.environ, PYTHONPATH=str(REPO)),
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    deadline = time.monotonic() + 30
    if when == "start-up":
        time.sleep(delay_s)  # uma is importing (the interpreter itself is up after ~0.1 s)
    else:  # the table is written before the first point runs; then the workers start
        while not (out / "sweep.csv").exists() and time.monotonic() < deadline:
            time.sleep(0.02)
        time.sleep(0.8 if when == "mid-run" else 0.05)
    if group:
        os.killpg(process.pid, number)
    else:
        process.send_signal(number)
    _, err = process.communicate(timeout=60)
    return process.returncode, err


@pytest.mark.parametrize(
    "number, group, when",
    [
        (signal.SIGINT, False, "start-up"),
        (signal.SIGINT, True, "mid-run"),  # Ctrl-C in a terminal
        (signal.SIGTERM, False, "mid-run"),
        # Each case spawns a sweep (about 3 s): the other moments run with `-m slow`.
        pytest.param(signal.SIGINT, True, "spawning", marks=pytest.mark.slow),
        pytest.param(signal.SIGINT, False, "mid-run", marks=pytest.mark.slow),
        pytest.param(signal.SIGTERM, False, "spawning", marks=pytest.mark.slow),
    ],
)
def test_an_interrupted_sweep_is_one_line(tmp_path, number, group, when):
    code, err = interrupt(tmp_path, number, group=group, when=when)
    assert "Traceback" not in err and err.count("\n") == 1, err
    if number == signal.SIGINT:
        # 130, or (when the signal lands in the interpreter's own start-up or shutdown, after
        # uma's line) death by SIGINT, which a shell reports as the same 130.
        assert code in (130, -signal.SIGINT), (code, err)
    else:
        assert code in (143, -signal.SIGTERM), (code, err)  # before its handler: killed
        if when == "mid-run":
            assert code == 143 and "interrupted (SIGTERM)" in err
