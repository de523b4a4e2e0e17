"""`uma.bench.timing.median_ms`: the median of the calls, so one slow call does not move it."""

import time

from uma.bench.timing import median_ms


def test_one_slow_call_does_not_move_the_median():
    delays_s = iter([0.2, 0.0, 0.0, 0.0, 0.0])
    calls = []

    def fn():
        calls.append(1)
        time.sleep(next(delays_s))

    assert median_ms(fn, repeats=5) < 40.0 and len(calls) == 5


def test_the_median_is_in_milliseconds():
    assert 4.0 <= median_ms(lambda: time.sleep(0.005), repeats=3) < 100.0
