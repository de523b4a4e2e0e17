"""`uma.bench.timing.median_ms`: the median of the calls, in ms, so one slow call does not move it.

The calls advance a fake clock (the module's `time.perf_counter`), so no figure here depends on
how loaded the machine is."""

import pytest

import uma.bench.timing as timing
from uma.bench.timing import median_ms


class FakeClock:
    """`perf_counter` that moves only when a call takes its time."""

    def __init__(self) -> None:
        self.now_s = 0.0

    def perf_counter(self) -> float:
        return self.now_s

    def taking(self, delays_s):
        delays = iter(delays_s)

        def fn():
            self.now_s += next(delays)

        return fn


def test_one_slow_call_does_not_move_the_median(monkeypatch):
    clock = FakeClock()
    monkeypatch.setattr(timing.time, "perf_counter", clock.perf_counter)
    assert median_ms(clock.taking([0.2, 0.001, 0.002, 0.001, 0.003]), repeats=5) == pytest.approx(
        2.0
    )


def test_the_median_is_in_milliseconds(monkeypatch):
    clock = FakeClock()
    monkeypatch.setattr(timing.time, "perf_counter", clock.perf_counter)
    assert median_ms(clock.taking([0.005, 0.004, 0.006]), repeats=3) == pytest.approx(5.0)
