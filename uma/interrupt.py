"""Ctrl-C while `uma` is loading: one line and exit 130 at once.

Python's own SIGINT handler raises KeyboardInterrupt wherever the main thread is. When that is
inside a callback the import machinery runs (a module lock's weakref callback), Python prints
"Exception ignored in ..." with a traceback and drops the interrupt, and the command runs on.
Until a command has started anything to clean up, exiting at once cannot be dropped that way.
Standard library only: `python -m uma` installs it before importing anything else of uma.
"""

from __future__ import annotations

import os
import signal
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["exit_at_once", "loading"]


def _exit(signum: int, frame: object) -> None:
    os.write(2, b"uma: interrupted\n")
    os._exit(130)


def exit_at_once() -> object:
    """From now on Ctrl-C exits at once; returns the handler it replaced (None off the main
    thread, where Python allows no handler and nothing changes)."""
    try:
        return signal.signal(signal.SIGINT, _exit)
    except ValueError:  # not the main thread
        return None


@contextmanager
def loading() -> Iterator[None]:
    """While the block runs Ctrl-C exits at once; after it, the handler there was before, or
    Python's own (KeyboardInterrupt) if that was this one."""
    previous = exit_at_once()
    try:
        yield
    finally:
        if previous is not None:
            restore = signal.default_int_handler if previous is _exit else previous
            signal.signal(signal.SIGINT, restore)
