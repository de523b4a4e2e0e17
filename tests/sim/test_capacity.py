import math

import pytest

from uma.sim.capacity import CapacitySchedule


def test_constant_rate_delivery_time():
    cap = CapacitySchedule([0.0], [1000.0])
    assert cap.finish_time_s(0.5, 1500) == pytest.approx(2.0)


def test_outage_inside_a_packets_transmission():
    # 1000 bit/s, outage from 1 s to 2 s, then 1000 bit/s: 1500 bits from t=0 leave at 2.5 s.
    cap = CapacitySchedule([0.0, 1.0, 2.0], [1000.0, 0.0, 1000.0])
    assert cap.finish_time_s(0.0, 1500) == pytest.approx(2.5)
    # Starting inside the outage waits for it to end.
    assert cap.finish_time_s(1.2, 500) == pytest.approx(2.5)


def test_rate_change_mid_packet():
    cap = CapacitySchedule([0.0, 1.0], [1000.0, 4000.0])
    # 600 bits before t=1 at 1 kbit/s from 0.4, then 400 bits at 4 kbit/s: 0.1 s more.
    assert cap.finish_time_s(0.4, 1000) == pytest.approx(1.1)


def test_capacity_that_never_returns_holds_forever():
    cap = CapacitySchedule([0.0, 1.0], [1000.0, 0.0])
    assert cap.finish_time_s(0.5, 1000) == math.inf
    assert cap.finish_time_s(0.5, 500) == pytest.approx(1.0)


def test_zero_size_leaves_at_once():
    cap = CapacitySchedule([0.0, 1.0], [0.0, 10.0])
    assert cap.finish_time_s(0.3, 0) == 0.3


def test_handover_gap_inserted_on_technology_change():
    class FakeTrace:
        times_s = [0.0, 10.0, 20.0]
        rates_kbps = [1000.0, 100.0, 100.0]
        technologies = ("WLAN", "3G", "3G")

    cap = CapacitySchedule.from_trace(FakeTrace(), handover_gap_s=0.5)
    assert cap.rate_kbps_at(9.9) == 1000.0
    assert cap.rate_kbps_at(10.2) == 0.0
    assert cap.rate_kbps_at(10.5) == 100.0
    assert cap.rate_kbps_at(20.2) == 100.0  # no change of technology, no gap
    # A 10 kbit packet starting at 9.99 s: 10 kbit by 10.0, then waits the gap.
    assert cap.finish_time_s(9.99, 10_000) == pytest.approx(10.0)
    assert cap.finish_time_s(9.995, 10_000) == pytest.approx(10.55)


def test_rejects_bad_schedules():
    with pytest.raises(ValueError):
        CapacitySchedule([0.0, 0.0], [1.0, 1.0])
    with pytest.raises(ValueError):
        CapacitySchedule([0.0], [-1.0])
    with pytest.raises(ValueError):
        CapacitySchedule([0.0], [float("nan")])


def test_min_rate_over_a_window_sees_every_step_it_touches():
    schedule = CapacitySchedule([0.0, 1.0, 2.0, 3.0], [500e3, 40e3, 300e3, 0.0])
    assert schedule.min_rate_kbps(0.0, 0.5) == 500.0
    assert schedule.min_rate_kbps(0.5, 1.0) == 40.0  # the step starting at the window's end
    assert schedule.min_rate_kbps(1.5, 2.5) == 40.0
    assert schedule.min_rate_kbps(2.0, 2.9) == 300.0
    assert schedule.min_rate_kbps(2.5, 9.0) == 0.0  # after the last start its rate holds


def test_bits_until_many_is_bits_until_at_every_time():
    import numpy as np

    from uma.sim.capacity import CapacitySchedule

    link = CapacitySchedule([0.0, 1.0, 2.5, 4.0], [8000.0, 0.0, 20000.0, 500.0])
    times = np.array([0.0, 0.4, 1.0, 1.7, 2.5, 3.9, 4.0, 9.0])
    assert np.allclose(link.bits_until_many(times), [link.bits_until(t) for t in times])
