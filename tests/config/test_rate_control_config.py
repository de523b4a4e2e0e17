"""The rate-control keys (issue 26): the controller and pacer on by default, retired keys refused."""

import pytest

from uma.config import load_scenario
from uma.config.retired import RETIRED
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


def test_the_controller_and_the_pacer_are_on_by_default(tmp_path):
    engine = _load(tmp_path, "  policy: throughput\n").engine
    assert engine.estimator.kind == "uma"
    assert engine.pacer.enabled and engine.pacer.rate_factor == 2.5


def test_the_kinds_are_read(tmp_path):
    assert _load(tmp_path, "  estimator: gcc\n").engine.estimator.kind == "gcc"
    assert _load(tmp_path, "  estimator: {kind: webrtc}\n").engine.estimator.kind == "webrtc"


@pytest.mark.parametrize(
    "engine, where",
    [
        ("  estimator: {queue_high_ms: 100}\n", "engine.estimator.queue_high_ms is retired"),
        ("  estimator: {increase_cap: 1.5}\n", "engine.estimator.increase_cap is retired"),
        ("  handover: {enabled: true}\n", "engine.handover is retired"),
        ("  pacer: {hold_after_ms: 150}\n", "engine.pacer.hold_after_ms is retired"),
        ("  pacer: {fit_frames: 2}\n", "engine.pacer.fit_frames is retired"),
        ("  mbc: {probe: false}\n", "engine.mbc.probe is retired"),
    ],
)
def test_a_retired_key_is_refused_naming_it_and_why(tmp_path, engine, where):
    with pytest.raises(
        ConfigError, match=r"s\.yaml:\d+ \(.*\): " + where.replace(".", r"\.")
    ) as err:
        _load(tmp_path, engine)
    path = tuple(where.split(" ")[0].split("."))
    assert RETIRED[path] in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize(
    "engine, where",
    [
        ("  pacer: {burst_ms: -1}\n", r"engine\.pacer\.burst_ms"),
        ("  pacer: {enabled: yes please}\n", r"engine\.pacer\.enabled"),
        ("  estimator: {kind: remb}\n", r"engine\.estimator\.kind"),
        ("  estimator: {min_kbps: 0}\n", r"engine\.estimator\.min_kbps"),
    ],
)
def test_bad_values_name_their_key(tmp_path, engine, where):
    with pytest.raises(ConfigError, match=where):
        _load(tmp_path, engine)
