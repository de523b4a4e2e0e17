"""The link's bound on each frame's delay, on hand-worked capacities."""

from __future__ import annotations

import numpy as np
import pytest

from uma.metrics.link_bound import bound_summary, frame_delay_bounds_s
from uma.sim.capacity import CapacitySchedule

STEP_S = 0.001


def bounds(link, delays, capture_s, size_bits):
    return frame_delay_bounds_s(
        link, delays.__getitem__, np.asarray(capture_s), size_bits=size_bits, step_s=STEP_S
    )


def test_a_constant_link_bounds_every_frame_by_one_transmission_and_the_delay():
    link = CapacitySchedule([0.0], [100_000.0], ["3G"])
    got = bounds(link, {"3G": 0.05}, [0.0, 0.5, 1.23], 1000)
    # 1,000 bits at 100 kbit/s: 10 ms, then 50 ms one way; the search lowers it by two steps.
    assert got == pytest.approx([0.060 - 2 * STEP_S] * 3, abs=1e-9)


def test_a_frame_captured_in_an_outage_waits_for_the_link_to_return():
    link = CapacitySchedule([0.0, 1.0, 3.0], [100_000.0, 0.0, 100_000.0], ["3G"] * 3)
    got = bounds(link, {"3G": 0.0}, [0.5, 1.0, 2.0, 2.999, 3.5], 1000)
    expected = [0.010, 2.010, 1.010, 0.011, 0.010]
    assert got == pytest.approx(np.array(expected) - 2 * STEP_S, abs=2e-6)


def test_a_packet_finishing_across_a_handover_to_less_delay_arrives_sooner():
    # GSM (400 ms one way) until 1 s, then 3G (50 ms): a frame captured at 0.9 s can finish in
    # GSM at 0.91 s and arrive at 1.31 s, or start at 0.99 s, finish as 3G begins (the
    # technology at the finish sets the delay, as in the simulation) and arrive at 1.05 s.
    link = CapacitySchedule([0.0, 1.0], [100_000.0, 100_000.0], ["GSM", "3G"])
    got = bounds(link, {"GSM": 0.4, "3G": 0.05}, [0.9], 1000)
    assert got[0] == pytest.approx(1.05 - 0.9 - 2 * STEP_S, abs=2e-6)


def test_a_link_that_never_returns_bounds_by_infinity():
    link = CapacitySchedule([0.0, 1.0], [100_000.0, 0.0], ["3G", "3G"])
    got = bounds(link, {"3G": 0.0}, [0.5, 1.5], 1000)
    assert got[0] == pytest.approx(0.008, abs=2e-6) and np.isinf(got[1])


def test_larger_packets_never_lower_the_bound():
    rng = np.random.default_rng(7)
    starts = np.concatenate(([0.0], np.sort(rng.uniform(0.0, 20.0, 40))))
    rates = rng.choice([0.0, 9_600.0, 40_000.0, 400_000.0], size=starts.size)
    rates[-1] = 40_000.0
    link = CapacitySchedule(starts, rates, ["GPRS"] * starts.size)
    capture_s = np.arange(0.0, 20.0, 0.04)
    small = bounds(link, {"GPRS": 0.2}, capture_s, 320)
    large = bounds(link, {"GPRS": 0.2}, capture_s, 9600)
    assert np.all(large >= small - 1e-12) and np.all(small >= 0.2 - 2 * STEP_S - 1e-12)


def test_the_summary_names_p95_median_and_shares():
    out = bound_summary(np.array([0.1] * 90 + [2.0] * 10), over_s=(1.0, 1.5))
    assert out == {
        "delay_p95_ms": 2000.0,
        "delay_median_ms": 100.0,
        "share_over_s": {"1": 0.1, "1.5": 0.1},
    }
    assert bound_summary(np.array([np.inf]))["delay_p95_ms"] is None


def test_bad_sizes_are_refused():
    link = CapacitySchedule([0.0], [1000.0])
    with pytest.raises(ValueError, match="size_bits"):
        frame_delay_bounds_s(link, lambda t: 0.0, np.array([0.0]), size_bits=0)


def test_a_long_run_is_searched_on_a_coarser_grid_and_stays_a_bound():
    from uma.metrics import link_bound

    link = CapacitySchedule([0.0, 100.0, 101.0], [100_000.0, 0.0, 100_000.0], ["3G"] * 3)
    capture_s = np.array([50.0, 100.5])
    fine = bounds(link, {"3G": 0.0}, capture_s, 1000)
    old = link_bound.MAX_GRID_POINTS
    try:
        link_bound.MAX_GRID_POINTS = 1000  # a 1 s horizon of 0.001 s steps would need ~161,000
        coarse = frame_delay_bounds_s(link, {"3G": 0.0}.__getitem__, capture_s, size_bits=1000)
    finally:
        link_bound.MAX_GRID_POINTS = old
    assert np.all(coarse <= fine + 1e-12) and np.all(coarse >= fine - 2 * 0.161 - 1e-9)
