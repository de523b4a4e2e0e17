"""Signals that arrive while workers are being spawned wait until the spawning is done."""

import os
import signal

import pytest

from uma.experiments.executor import _signals_held


class Stop(Exception):
    pass


def test_a_sigterm_inside_the_block_is_raised_after_it():
    def stop(number, frame):
        raise Stop(number)

    previous = signal.signal(signal.SIGTERM, stop)
    reached_end = False
    try:
        with pytest.raises(Stop), _signals_held():
            os.kill(os.getpid(), signal.SIGTERM)
            reached_end = True  # the handler did not interrupt the block
        assert reached_end
        assert signal.getsignal(signal.SIGTERM) is stop
    finally:
        signal.signal(signal.SIGTERM, previous)


def test_without_a_signal_nothing_is_raised_and_handlers_are_restored():
    before = signal.getsignal(signal.SIGINT)
    with _signals_held():
        pass
    assert signal.getsignal(signal.SIGINT) is before
