"""The sender's stream computed once (`uma.sim.uplink`): a run that takes it from a memo gives
byte for byte what computing afresh gives, also when it runs on past what the memo holds."""

import pytest

from uma.config.scenario import Scenario
from uma.sim import run_scenario
from uma.sim.summary import run_metrics
from uma.sim.uplink import UplinkMemo


def _scenario(duration_s: float, **sender) -> Scenario:
    return Scenario.model_validate(
        {
            "name": "uplink",
            "seed": 5,
            "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
            "route": [{"technology": "3G", "duration_s": 4.0}],
            "duration_s": duration_s,
            "sender": {"rate_kbps": 600.0} | sender,
            "metrics": {"ssim": False, "workers": 0},
        }
    )


def _files(result) -> tuple[str, dict]:
    return result.log.to_csv(), run_metrics(result)


@pytest.fixture(scope="module")
def fresh():
    return {d: _files(run_scenario(_scenario(d))) for d in (1.2, 2.0)}


def test_a_run_taking_the_stream_from_the_memo_is_the_run_computed_afresh(fresh):
    memo = UplinkMemo()
    assert _files(run_scenario(_scenario(1.2), uplink=memo)) == fresh[1.2]  # fills it
    assert memo.hits == 0 and len(memo.frames) == 30
    assert _files(run_scenario(_scenario(1.2), uplink=memo)) == fresh[1.2]  # takes it
    assert memo.hits == 30


def test_a_longer_run_catches_up_where_the_memo_ends(fresh):
    memo = UplinkMemo()
    run_scenario(_scenario(1.2), uplink=memo)
    assert _files(run_scenario(_scenario(2.0), uplink=memo)) == fresh[2.0]
    assert memo.hits == 30 and len(memo.frames) == 50


def test_another_sender_setting_is_another_stream():
    memo = UplinkMemo()
    run_scenario(_scenario(0.4), uplink=memo)
    run_scenario(_scenario(0.4, rate_kbps=300.0), uplink=memo)
    assert memo.hits == 0 and len(memo.frames) == 20


def test_a_stream_computed_ahead_is_the_one_a_run_computes(fresh):
    from uma.sim.coders import compute_uplink
    from uma.sim.sources import open_source

    scenario = _scenario(1.2)
    source = open_source(scenario.source, seed=scenario.seed)
    frames = [frame for _, frame in zip(range(30), source.frames(), strict=False)]
    memo = UplinkMemo()
    compute_uplink(memo, scenario, frames, width=176, height=144, fps=25.0)
    assert _files(run_scenario(scenario, uplink=memo)) == fresh[1.2]
    assert memo.hits == 30
