"""Issue 26's "one set of defaults": no shipped scenario sets a rate-control key."""

from pathlib import Path

import pytest
import yaml

SCENARIOS = sorted((Path(__file__).parents[2] / "scenarios").glob("*.yaml"))
# The engine's rate-control keys: the controller's and the pacer's sections whole, and the
# rate policy's and skip rule's own keys (`uma.config.engine.EngineConfig`).
RATE_CONTROL = {"estimator", "pacer", "safety", "up_hold_ms", "climb", "drained_queue",
                "rung_floor", "stale_reports", "max_backlog_ms", "presume_lost_ms",
                "probe_interval_ms"}  # fmt: skip


def rate_control_keys(text: str) -> set[str]:
    """The rate-control keys a scenario's YAML sets under `engine`."""
    engine = (yaml.safe_load(text) or {}).get("engine") or {}
    return RATE_CONTROL & set(engine)


def test_there_are_shipped_scenarios():
    assert len(SCENARIOS) >= 5


@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.name)
def test_no_shipped_scenario_sets_a_rate_control_key(path):
    assert rate_control_keys(path.read_text(encoding="utf-8")) == set(), path.name


def test_the_check_sees_a_key_that_is_set():
    assert rate_control_keys("engine: {policy: throughput, pacer: {rate_factor: 1.5}}") == {"pacer"}
    assert rate_control_keys("engine:\n  estimator: {kind: gcc}\n  safety: 0.9\n") == {
        "estimator",
        "safety",
    }
