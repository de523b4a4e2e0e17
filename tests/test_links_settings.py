"""`scripts/links_settings.py`'s `--set`: a setting reaches uma's controller even where the
scenario names the same key (before session 29 the scenario's value silently won)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import links_settings  # noqa: E402

import uma.engine.rate as rate  # noqa: E402
from uma.config.engine import EstimatorConfig  # noqa: E402
from uma.config.scenario import EngineConfig, FeedbackConfig  # noqa: E402


@pytest.mark.parametrize("overrides", [{"judge_silence": True}, {"judge_fraction": 0.5}])
def test_a_set_wins_over_the_scenario_s_key(monkeypatch, overrides):
    monkeypatch.setattr(rate, "UmaSettings", rate.UmaSettings)  # undone after the test
    links_settings.override_settings(overrides)
    engine = EngineConfig(estimator=EstimatorConfig(judge_silence=False))
    settings = rate.make_rate(engine, FeedbackConfig()).controller.settings
    for key, value in overrides.items():
        assert getattr(settings, key) == value
    assert settings.judge_silence is overrides.get("judge_silence", False)
