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


@pytest.mark.parametrize(
    ("case", "says"),
    [
        ("x", "expected TRACE:OFFSET_S:DURATION_S"),
        ("no-such-trace.csv:0:10", "no trace file no-such-trace.csv"),
        ("{trace}:-1:10", "expected OFFSET_S >= 0 and DURATION_S > 0"),
        ("{trace}:0:nan", "expected OFFSET_S >= 0 and DURATION_S > 0"),
        ("{trace}:0:ten", "expected TRACE:OFFSET_S:DURATION_S"),
    ],
)
def test_a_bad_case_is_one_line_and_exit_2(tmp_path, capsys, case, says):
    trace = tmp_path / "link.csv"
    trace.write_text("0,1000\n")
    args = links_settings.argparse.Namespace(case=[case.format(trace=trace)], engines="uma")
    with pytest.raises(SystemExit) as stopped:
        links_settings.cases(args)
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err


def test_good_cases_and_keys_parse(tmp_path):
    trace = tmp_path / "link.csv"
    trace.write_text("0,1000\n")
    args = links_settings.argparse.Namespace(case=[f"{trace}:5:60"], engines="uma,gcc")
    assert links_settings.cases(args) == [
        (str(trace), 5.0, 60.0, "uma"),
        (str(trace), 5.0, 60.0, "gcc"),
    ]
    assert links_settings.json_keys(["climb=\"stream\"", "calm_ms=2000"]) == {
        "climb": "stream", "calm_ms": 2000,
    }  # fmt: skip


@pytest.mark.parametrize("item", ["climb", "=1", "calm_ms={"])
def test_a_bad_key_is_one_line_and_exit_2(capsys, item):
    with pytest.raises(SystemExit) as stopped:
        links_settings.json_keys([item])
    assert stopped.value.code == 2
    assert capsys.readouterr().err.count("\n") == 1
