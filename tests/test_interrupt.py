"""Ctrl-C while uma loads exits at once; after loading, Python's KeyboardInterrupt is back."""

import os
import signal
import subprocess
import sys
from pathlib import Path

from uma.interrupt import exit_at_once, loading

REPO = Path(__file__).resolve().parents[1]


def test_loading_puts_back_the_handler_it_found():
    before = signal.getsignal(signal.SIGINT)
    with loading():
        assert signal.getsignal(signal.SIGINT) is not before
    assert signal.getsignal(signal.SIGINT) is before


def test_after_exit_at_once_loading_ends_in_keyboard_interrupt():
    before = signal.getsignal(signal.SIGINT)
    try:
        exit_at_once()
        with loading():
            pass
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, before)


def test_an_interrupt_inside_an_import_callback_is_not_dropped():
    """The case Python's own handler loses: the signal lands in a weakref callback."""
    code = (
        "import os, signal, weakref\n"
        "from uma.interrupt import exit_at_once\n"
        "exit_at_once()\n"
        "class A: pass\n"
        "a = A()\n"
        "w = weakref.ref(a, lambda r: os.kill(os.getpid(), signal.SIGINT) or sum(range(10**5)))\n"
        "del a\n"
        "print('ran on')\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(REPO)),
        timeout=30,
    )
    assert (done.returncode, done.stdout, done.stderr) == (130, "", "uma: interrupted\n")
