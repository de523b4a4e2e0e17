"""The rate-control keys of issue 19: pacer, delay trend, handover; off by default, checked."""

import pytest

from uma.config import load_scenario
from uma.errors import ConfigError

MINIMAL = """\
name: demo
route:
  - technology: WLAN
    duration_s: 10
"""


def _load(tmp_path, engine: str):
    path = tmp_path / "s.yaml"
    path.write_text(MINIMAL + "engine:\n" + engine)
    return load_scenario(path)


def test_off_by_default(tmp_path):
    engine = _load(tmp_path, "  policy: throughput\n").engine
    assert not engine.pacer.enabled and not engine.handover.enabled
    assert engine.estimator.trend_window_s == 0.0 and engine.estimator.increase_cap == 3.0


def test_keys_are_read(tmp_path):
    engine = _load(
        tmp_path,
        "  pacer: {enabled: true, hold_after_ms: 250, fit_frames: 2}\n"
        "  handover: {enabled: true, priors_kbps: {GPRS: 30}}\n"
        "  estimator: {trend_window_s: 1.0, increase_cap: 1.5}\n",
    ).engine
    assert engine.pacer.hold_after_ms == 250 and engine.pacer.fit_frames == 2
    assert engine.handover.priors_kbps == {"GPRS": 30}
    assert engine.estimator.trend_window_s == 1.0


@pytest.mark.parametrize(
    "engine, where",
    [
        ("  handover: {priors_kbps: {GPRSS: 30}}\n", r"engine\.handover\.priors_kbps"),
        ("  handover: {priors_kbps: {GPRS: 0}}\n", r"engine\.handover\.priors_kbps\.GPRS"),
        ("  pacer: {burst_ms: -1}\n", r"engine\.pacer\.burst_ms"),
        ("  pacer: {enabled: yes please}\n", r"engine\.pacer\.enabled"),
        ("  estimator: {increase_cap: 0.5}\n", r"engine\.estimator\.increase_cap"),
    ],
)
def test_bad_values_name_their_key(tmp_path, engine, where):
    with pytest.raises(ConfigError, match=where):
        _load(tmp_path, engine)
