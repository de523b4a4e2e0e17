import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.errors import TraceError
from uma.traces import Trace, concatenate


def three_steps() -> Trace:
    return Trace([0.0, 1.0, 3.0], [10.0, 0.0, 30.0], ("WLAN", "3G", ""), 5.0, "t")


def test_rate_at_step_edges():
    trace = three_steps()
    assert trace.rate_kbps_at(0.0) == 10
    assert trace.rate_kbps_at(np.nextafter(1.0, 0.0)) == 10
    assert trace.rate_kbps_at(1.0) == 0  # an edge belongs to the step it starts
    assert trace.rate_kbps_at(2.999) == 0
    assert trace.rate_kbps_at(3.0) == 30
    assert trace.rate_kbps_at(5.0) == 30  # the end belongs to the last step
    assert trace.technology_at(1.0) == "3G"
    assert trace.technology_at(4.0) == ""
    for outside in (-1e-12, 5.000001, float("nan")):
        with pytest.raises(TraceError, match="outside 0-5.0 s"):
            trace.rate_kbps_at(outside)


def test_mean_widths_and_len():
    trace = three_steps()
    assert trace.widths_s.tolist() == [1.0, 2.0, 2.0]
    assert trace.mean_rate_kbps == pytest.approx((10 + 0 + 60) / 5)
    assert len(trace) == 3


def test_window_is_rebased_and_cuts_steps():
    part = three_steps().window(0.5, 3.0)
    assert part.times_s.tolist() == [0.0, 0.5, 2.5]
    assert part.rates_kbps.tolist() == [10.0, 0.0, 30.0]
    assert part.technologies == ("WLAN", "3G", "")
    assert part.duration_s == 3.0
    inside = three_steps().window(1.0, 2.0)  # exactly one step, the next starts at the end
    assert inside.times_s.tolist() == [0.0] and inside.rates_kbps.tolist() == [0.0]
    for start, length in ((4.0, 2.0), (-1.0, 1.0), (1.0, 0.0), (5.0, 1.0)):
        with pytest.raises(TraceError, match="expected a window inside"):
            three_steps().window(start, length)


def test_concat_keeps_every_step():
    a = Trace.constant(100.0, 2.0, technology="GPRS", source="a")
    b = Trace.constant(100.0, 3.0, technology="GPRS", source="b")
    both = a.concat(b)
    assert both.times_s.tolist() == [0.0, 2.0]  # equal neighbours are not merged
    assert both.duration_s == 5.0
    assert both.source == "a+b"
    assert concatenate([a, a, a]).source == "a"


def test_with_technology_and_scaled():
    trace = three_steps()
    assert trace.with_technology("hspa+").technologies == ("3G", "3G", "3G")
    assert trace.with_technology("GSM", only_unlabelled=True).technologies == ("WLAN", "3G", "GSM")
    with pytest.raises(TraceError, match="got 'Carrier pigeon'"):
        trace.with_technology("Carrier pigeon")
    assert trace.scaled(0.5).rates_kbps.tolist() == [5.0, 0.0, 15.0]
    with pytest.raises(TraceError, match="scale"):
        trace.scaled(-1.0)


def test_trace_is_immutable_and_copies_its_input():
    times = np.array([0.0, 1.0])
    trace = Trace(times, [1.0, 2.0], ("", ""), 2.0)
    times[1] = 5.0
    assert trace.times_s[1] == 1.0
    with pytest.raises(ValueError):
        trace.rates_kbps[0] = 3.0
    with pytest.raises(AttributeError):
        trace.duration_s = 3.0


def test_equality_is_content():
    assert three_steps() == Trace([0, 1, 3], [10, 0, 30], ["WLAN", "3G", ""], 5, "other name")
    assert three_steps() != three_steps().scaled(2.0)
    assert hash(three_steps()) == hash(Trace([0, 1, 3], [10, 0, 30], ["WLAN", "3G", ""], 5))


@pytest.mark.parametrize(
    "times, rates, techs, duration, message",
    [
        ([], [], (), 1.0, "no samples"),
        ([0.0], [np.nan], ("",), 1.0, "step 0: expected a finite rate >= 0, got nan"),
        ([0.0], [np.inf], ("",), 1.0, "finite rate"),
        ([0.0, 1.0], [1.0, -2.0], ("", ""), 2.0, "step 1: expected a finite rate >= 0"),
        ([0.5], [1.0], ("",), 1.0, "first step to start at 0 s"),
        ([0.0, 2.0, 1.0], [1.0] * 3, ("",) * 3, 3.0, "step 2 starts at 1.0 s"),
        ([0.0, 0.0], [1.0] * 2, ("",) * 2, 3.0, "step 1 starts at 0.0 s"),
        ([0.0, np.nan], [1.0] * 2, ("",) * 2, 3.0, "step 1 starts at nan"),
        ([0.0, 2.0], [1.0, 1.0], ("", ""), 2.0, "duration after the last step's start"),
        ([0.0], [1.0], ("",), float("inf"), "duration after"),
        ([0.0], [1.0], ("HSPA+",), 1.0, "step 0: expected a technology among"),
        ([0.0], [1.0, 2.0], ("",), 1.0, "one of each per step"),
        ([0.0], ["fast"], ("",), 1.0, "rates_kbps must be numbers"),
    ],
)
def test_trace_validation(times, rates, techs, duration, message):
    with pytest.raises(TraceError, match=message.replace("+", r"\+")):
        Trace(times, rates, techs, duration, "t")


widths = st.lists(st.floats(min_value=0.01, max_value=100.0), min_size=1, max_size=20)


def build(ws: list[float], seed: int) -> Trace:
    rates = np.random.default_rng(seed).uniform(0, 1000, len(ws))
    times = np.concatenate(([0.0], np.cumsum(ws)[:-1]))
    return Trace(times, rates, ("",) * len(ws), float(np.sum(ws)), "p")


@given(ws=widths, seed=st.integers(0, 100), a=st.floats(0, 1), b=st.floats(0.001, 1))
@settings(max_examples=100, deadline=None)
def test_window_agrees_with_the_trace_and_keeps_the_bits(ws, seed, a, b):
    trace = build(ws, seed)
    start = a * trace.duration_s * 0.999
    length = b * (trace.duration_s - start)
    part = trace.window(start, length)
    for f in (0.0, 0.3, 0.77, 0.999):
        assert part.rate_kbps_at(f * length) == trace.rate_kbps_at(start + f * length)
    # bits in the window = integral of the original over [start, start + length], exactly: each
    # step's rate times its overlap with the window (a sampled integral is too coarse beside a
    # narrow step of high rate, which hypothesis finds).
    ends = np.append(trace.times_s[1:], trace.duration_s)
    overlap = np.clip(np.minimum(ends, start + length) - np.maximum(trace.times_s, start), 0, None)
    expected = float(np.sum(trace.rates_kbps * overlap))
    assert part.mean_rate_kbps * length == pytest.approx(expected, rel=1e-9, abs=1e-9 * length)


@given(first=widths, second=widths, seed=st.integers(0, 100))
@settings(max_examples=60, deadline=None)
def test_concat_adds_durations_and_bits(first, second, seed):
    a, b = build(first, seed), build(second, seed + 1)
    both = a.concat(b)
    assert both.duration_s == pytest.approx(a.duration_s + b.duration_s)
    bits = a.mean_rate_kbps * a.duration_s + b.mean_rate_kbps * b.duration_s
    assert both.mean_rate_kbps * both.duration_s == pytest.approx(bits)
    assert both.rate_kbps_at(a.duration_s) == b.rates_kbps[0]
