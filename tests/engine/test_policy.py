import pytest

from uma.engine.policy import (
    PolicyView,
    fixed_policy,
    highest_fitting,
    oracle_policy,
    throughput_policy,
)

RATES = (30.0, 100.0, 300.0, 1000.0)


def view(**kw):
    base = dict(
        now_s=10.0,
        rung_rates_kbps=RATES,
        current_rung=1,
        last_switch_s=0.0,
        estimate_kbps=400.0,
        safety=1.0,
        up_hold_s=2.0,
    )
    base.update(kw)
    return PolicyView(**base)


def test_highest_fitting():
    assert highest_fitting(RATES, 5.0) == 0
    assert highest_fitting(RATES, 100.0) == 1
    assert highest_fitting(RATES, 5000.0) == 3


def test_throughput_goes_down_at_once():
    assert throughput_policy(view(current_rung=3, estimate_kbps=120.0, last_switch_s=9.9)) == 1


def test_throughput_goes_up_one_rung_after_hold():
    assert throughput_policy(view(current_rung=0, estimate_kbps=5000.0, last_switch_s=9.0)) == 0
    assert throughput_policy(view(current_rung=0, estimate_kbps=5000.0, last_switch_s=7.0)) == 1


def test_safety_margin_applies():
    assert throughput_policy(view(current_rung=2, estimate_kbps=320.0, safety=0.85)) == 1


def test_oracle_uses_true_capacity_and_needs_it():
    assert oracle_policy(view(capacity_kbps=1200.0, estimate_kbps=1.0)) == 3
    with pytest.raises(ValueError):
        oracle_policy(view())


def test_fixed_policy_clamps():
    assert fixed_policy(view(fixed_rung=2)) == 2
    assert fixed_policy(view(fixed_rung=9)) == 3
