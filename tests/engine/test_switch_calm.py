"""`engine.switching.calm_ms`: no switch from the model codec back to H.264 until that long
after the last silence cut (hand-worked: on MBC since 0 s, the minimum dwell 3 s, a budget of
100 kbit/s over the 60 kbit/s threshold, a silence cut at 4.0 s)."""

from __future__ import annotations

import pytest

from uma.config import EngineConfig
from uma.config.engine import SwitchingConfig
from uma.engine.policy import (
    SwitchSettings,
    SwitchView,
    predictive_switch,
    switch_settings,
    threshold_switch,
)
from uma.engine.position import Position

MODEL, LADDER = SwitchSettings().model, SwitchSettings().ladder


def _codecs(policy, calm_s: float, times_s: tuple[float, ...]) -> list[str]:
    settings = SwitchSettings(min_dwell_s=3.0, calm_s=calm_s)
    return [policy(SwitchView(t, MODEL, 0.0, 100.0, cut_s=4.0), settings) for t in times_s]


@pytest.mark.parametrize("policy", [threshold_switch, predictive_switch])
def test_the_model_codec_is_kept_until_calm_after_a_silence_cut(policy):
    """With 2 s of calm: 1.0 and 1.9 s after the cut the budget is over the threshold and the
    dwell is done, yet MBC stays; at 2.0 s after it the switch to H.264 is made."""
    times_s = (5.0, 5.9, 6.0)
    assert _codecs(policy, 2.0, times_s) == [MODEL, MODEL, LADDER]


@pytest.mark.parametrize("policy", [threshold_switch, predictive_switch])
def test_without_calm_the_switch_back_is_made_at_once(policy):
    assert _codecs(policy, 0.0, (5.0, 5.9, 6.0)) == [LADDER, LADDER, LADDER]


def test_calm_does_not_delay_the_switch_down_nor_one_without_a_cut():
    settings = SwitchSettings(min_dwell_s=3.0, calm_s=2.0)
    down = SwitchView(5.0, LADDER, 0.0, 10.0, cut_s=4.9)
    assert threshold_switch(down, settings) == MODEL
    never_cut = SwitchView(5.0, MODEL, 0.0, 100.0)
    assert threshold_switch(never_cut, settings) == LADDER


def test_the_key_reaches_the_settings_and_is_off_by_default():
    assert SwitchingConfig().calm_ms == 0.0
    config = EngineConfig(switching=SwitchingConfig(policy="threshold", calm_ms=2500.0))
    assert switch_settings(config, ladder=LADDER, model=MODEL).calm_s == 2.5
    assert switch_settings(EngineConfig(), ladder=LADDER, model=MODEL).calm_s == 0.0


class _Switcher:
    """Records the `cut_s` the position hands on (the switching decision itself is above)."""

    def __init__(self) -> None:
        self.cuts_s: list[float] = []

    def choose(self, view, policy, *, since_s, budget_kbps, budget_ahead_kbps, cut_s):
        self.cuts_s.append(cut_s)
        return 0, None, []


def test_the_position_remembers_when_the_estimate_was_last_cut():
    config = EngineConfig(switching=SwitchingConfig(policy="threshold", calm_ms=2000.0))
    switcher = _Switcher()
    position = Position(config, (), ladder=_Ladder(), switcher=switcher, policy=None, rung=0)
    for now_s, cut in ((1.0, False), (2.0, True), (3.0, False), (4.5, True), (5.0, False)):
        position.choose(
            now_s, estimate_kbps=50.0, capacity_kbps=None, budget_kbps=42.5,
            lowest_kbps=None, cut=cut,
        )  # fmt: skip
    assert switcher.cuts_s == [float("-inf"), 2.0, 2.0, 4.5, 4.5]


class _Ladder:
    def allowed(self, now_s: float) -> tuple[int, ...]:
        return (0,)
