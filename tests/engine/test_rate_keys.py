"""`engine.estimator`'s switches for uma's controller reach its settings (off by default)."""

from __future__ import annotations

import pytest

from uma.config.engine import EstimatorConfig
from uma.config.scenario import EngineConfig, FeedbackConfig
from uma.engine.rate import make_rate

KEYS = (
    "recover_after_silence",
    "overdue_in_any_report",
    "no_probe_while_owed",
    "no_probe_into_silence",
    "take_queued_drop",
)
ON_KEYS = ("fixed_due_time", "no_probe_while_paused")  # adopted (docs/rate-control.md, rc14)


@pytest.mark.parametrize("key", KEYS)
def test_an_estimator_switch_reaches_uma_s_controller_and_is_off_by_default(key):
    default = make_rate(EngineConfig(estimator=EstimatorConfig()), FeedbackConfig())
    assert getattr(default.controller.settings, key) is False
    on = make_rate(EngineConfig(estimator=EstimatorConfig(**{key: True})), FeedbackConfig())
    assert getattr(on.controller.settings, key) is True
    others = [k for k in KEYS if k != key]
    assert not any(getattr(on.controller.settings, k) for k in others)


@pytest.mark.parametrize("key", ON_KEYS)
def test_an_adopted_estimator_switch_is_on_by_default_and_can_be_turned_off(key):
    default = make_rate(EngineConfig(estimator=EstimatorConfig()), FeedbackConfig())
    assert getattr(default.controller.settings, key) is True
    off = make_rate(EngineConfig(estimator=EstimatorConfig(**{key: False})), FeedbackConfig())
    assert getattr(off.controller.settings, key) is False
