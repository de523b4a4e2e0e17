import pytest

from uma.engine.points import OperatingPoint
from uma.engine.policy import (
    PolicyView,
    SwitchSettings,
    SwitchView,
    fixed_policy,
    highest_fitting,
    oracle_policy,
    threshold_switch,
    throughput_policy,
)

RATES = (30.0, 100.0, 300.0, 1000.0)


def view(**kw):
    base = dict(
        now_s=10.0,
        points=tuple(OperatingPoint("h264", rate, 25.0, 176, 144) for rate in RATES),
        current=1,
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
    assert throughput_policy(view(current=3, estimate_kbps=120.0, last_switch_s=9.9)) == 1


def test_throughput_goes_up_one_rung_after_hold():
    assert throughput_policy(view(current=0, estimate_kbps=5000.0, last_switch_s=9.0)) == 0
    assert throughput_policy(view(current=0, estimate_kbps=5000.0, last_switch_s=7.0)) == 1


def test_safety_margin_applies():
    assert throughput_policy(view(current=2, estimate_kbps=320.0, safety=0.85)) == 1


def test_oracle_uses_true_capacity_and_needs_it():
    # The throughput policy with a perfect estimate: down at once, up one rung after the hold.
    assert oracle_policy(view(current=3, capacity_kbps=120.0, estimate_kbps=5000.0)) == 1
    assert oracle_policy(view(capacity_kbps=1200.0, estimate_kbps=1.0)) == 2
    assert oracle_policy(view(capacity_kbps=1200.0, last_switch_s=9.0)) == 1
    with pytest.raises(ValueError):
        oracle_policy(view())


def test_fixed_policy_clamps():
    assert fixed_policy(view(fixed_rung=2)) == 2
    assert fixed_policy(view(fixed_rung=9)) == 3


# --- switching: thresholds with hysteresis and a minimum dwell, on synthetic sequences ------


def run_switching(budgets_kbps, *, settings, step_s=0.5):
    """Feed a budget sequence through the policy as the engine would; the codec per step."""
    codec, since_s, out = "h264", 0.0, []
    for i, budget in enumerate(budgets_kbps):
        now_s = i * step_s
        wanted = threshold_switch(SwitchView(now_s, codec, since_s, budget), settings)
        if wanted != codec:
            codec, since_s = wanted, now_s
        out.append(codec)
    return out


def test_threshold_switches_down_below_and_up_above_only():
    settings = SwitchSettings(to_model_below_kbps=30, to_ladder_above_kbps=60, min_dwell_s=0.0)
    codecs = run_switching([100, 40, 29, 45, 59, 61, 40], settings=settings)
    # 40 and 45, 59 lie in the hysteresis band: no change there in either direction.
    assert codecs == ["h264", "h264", "mbc", "mbc", "mbc", "h264", "h264"]


def test_threshold_never_flaps_on_an_estimate_oscillating_inside_the_band():
    settings = SwitchSettings(to_model_below_kbps=30, to_ladder_above_kbps=60, min_dwell_s=0.0)
    codecs = run_switching([25] + [31, 59] * 20, settings=settings)
    assert codecs == ["mbc"] * 41


def test_minimum_dwell_holds_each_codec():
    settings = SwitchSettings(to_model_below_kbps=30, to_ladder_above_kbps=60, min_dwell_s=2.0)
    # Budget collapses at 3.0 s (step 6), recovers at 3.5 s; dwell keeps MBC until 5.0 s.
    budgets = [100] * 6 + [10] + [100] * 10
    codecs = run_switching(budgets, settings=settings)
    assert codecs.index("mbc") == 6
    assert codecs[6:10] == ["mbc"] * 4  # 3.0 to 4.5 s: within the dwell
    assert codecs[10] == "h264"  # 5.0 s: dwell over, budget above the upper threshold
    # A collapse within the dwell after arriving on H.264 (at 0 s) waits until 2.0 s.
    assert run_switching([10] * 5, settings=settings) == ["h264"] * 4 + ["mbc"]


def test_switch_settings_refuse_an_inverted_band():
    with pytest.raises(ValueError, match="to_model_below_kbps"):
        SwitchSettings(to_model_below_kbps=60, to_ladder_above_kbps=30)


def test_predictive_switches_before_a_scripted_boundary_and_holds_through_it():
    from uma.engine.policy import predictive_switch

    settings = SwitchSettings(min_dwell_s=0.0, lookahead_s=3.0)
    coverage = ((0.0, "WLAN"), (10.0, "GSM"), (20.0, "3G"))

    def codec_at(now_s, codec="h264", budget_kbps=1000.0):
        view = SwitchView(now_s, codec, 0.0, budget_kbps, coverage=coverage)
        return predictive_switch(view, settings)

    assert codec_at(6.9) == "h264"  # the budget is high and GSM is 3.1 s away
    assert codec_at(7.0) == "mbc"  # 3 s before the boundary, whatever the budget
    # On MBC inside GSM a budget spike does not bring H.264 back...
    assert codec_at(15.0, "mbc", budget_kbps=500.0) == "mbc"
    # ...after GSM (3G) the thresholds decide again.
    assert codec_at(20.5, "mbc", budget_kbps=500.0) == "h264"
    assert codec_at(20.5, "mbc", budget_kbps=40.0) == "mbc"  # inside the hysteresis band
    # Without a coverage map it is the threshold policy.
    view = SwitchView(7.0, "h264", 0.0, 1000.0)
    assert predictive_switch(view, settings) == "h264"


def test_oracle_switches_before_the_capacity_falls_and_returns_when_the_window_clears():
    from uma.engine.policy import oracle_switch

    settings = SwitchSettings(to_model_below_kbps=30, to_ladder_above_kbps=60, min_dwell_s=5.0)

    def codec_at(ahead_kbps, codec="h264"):
        view = SwitchView(1.0, codec, 0.0, 1000.0, budget_ahead_kbps=ahead_kbps)
        return oracle_switch(view, settings)

    # The budget now is 1000 kbit/s; only the window ahead counts (and no dwell holds it).
    assert codec_at(20.0) == "mbc"
    assert codec_at(45.0) == "h264"  # on H.264, a window inside the band keeps H.264
    assert codec_at(45.0, "mbc") == "mbc"  # on MBC it keeps MBC until the window clears
    assert codec_at(61.0, "mbc") == "h264"
    with pytest.raises(ValueError, match="capacity ahead"):
        oracle_switch(SwitchView(1.0, "h264", 0.0, 1000.0), settings)
