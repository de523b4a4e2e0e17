"""The playout replay: the display rule run on a run's recorded decoded frames gives exactly the
display a full run gives, with the run's own playout and with any other."""

import dataclasses

import numpy as np
import pytest

from uma.config import load_scenario
from uma.config.scenario import AdaptivePlayoutConfig, ReceiverConfig
from uma.sim import run_scenario
from uma.sim.playout import FixedPlayout
from uma.sim.playout_replay import (
    DisplayRule,
    newest_decoded,
    recording_of,
    replay,
)

# The model-aided refresh puts pictures the playout is not told of.
REFRESH = """\
name: replay-refresh
seed: 3
source: {kind: talking-head, width: 176, height: 144, fps: 25}
route:
  - {technology: WLAN, duration_s: 2}
  - {technology: GPRS, duration_s: 5}
engine:
  policy: oracle
  switching: {policy: threshold, min_dwell_ms: 1000}
  mbc: {refresh: {enabled: true}}
receiver: {playout: adaptive}
metrics: {workers: 0}
"""


def scenario(tmp_path, text, receiver=None):
    path = tmp_path / "s.yaml"
    path.write_text(text)
    loaded = load_scenario(path)
    if receiver is not None:
        loaded = loaded.model_copy(update={"receiver": receiver})
    return loaded


def assert_same_display(out, result):
    log = result.log
    np.testing.assert_array_equal(out.display_ms, log["display_ms"])
    np.testing.assert_array_equal(out.shown_frame, log["shown_frame"])
    np.testing.assert_array_equal(out.frozen, log["frozen"])


@pytest.fixture(scope="module")
def short(tmp_path_factory, playout_short_yaml):
    return run_scenario(scenario(tmp_path_factory.mktemp("short"), playout_short_yaml))


def test_the_recording_is_the_decoded_frames_in_decode_order(short):
    decoded = short.decoded
    assert len(decoded) == int(short.log["decoded"].sum()) > 20
    times = [entry.decode_s for entry in decoded]
    assert times == sorted(times)
    for entry in decoded:
        assert short.log["arrival_ms"][entry.frame] == entry.decode_s * 1000.0
        assert entry.capture_s == short.log["capture_ms"][entry.frame] / 1000.0
    assert short.log["frozen"].any() and not short.log["frozen"].all()


def test_replay_of_the_runs_own_playout_is_exact(short):
    assert_same_display(replay(recording_of(short)), short)


@pytest.mark.parametrize(
    "adaptive",
    [
        AdaptivePlayoutConfig(rise_window_s=0.5, margin_ms=100),
        AdaptivePlayoutConfig(
            window_s=1.0, floor_window_s=0.5, max_decrease_ms_per_s=200, catch_up_s=0.5
        ),
        AdaptivePlayoutConfig(reject_bursts=True, percentile=50.0, margin_ms=0),
    ],
)
def test_replay_of_another_setting_equals_its_full_run(
    tmp_path, short, adaptive, playout_short_yaml
):
    receiver = short.scenario.receiver.model_copy(update={"adaptive": adaptive})
    full = run_scenario(scenario(tmp_path, playout_short_yaml, receiver))
    out = replay(recording_of(short), adaptive)
    assert_same_display(out, full)
    # It is another display than the recorded run's: the check can tell them apart.
    assert not np.array_equal(out.display_ms, short.log["display_ms"])


def test_replay_of_a_fixed_playout_equals_its_full_run(tmp_path, short, playout_short_yaml):
    receiver = ReceiverConfig(playout="fixed", playout_delay_ms=300)
    full = run_scenario(scenario(tmp_path, playout_short_yaml, receiver))
    assert_same_display(replay(recording_of(short), receiver=receiver), full)
    assert_same_display(replay(recording_of(full)), full)


def test_a_recording_missing_frames_replays_another_display(short):
    recording = recording_of(short)
    thinned = dataclasses.replace(recording, decoded=recording.decoded[::2])
    out = replay(thinned)
    assert not np.array_equal(out.shown_frame, short.log["shown_frame"])


def test_replay_with_the_model_aided_refresh_is_exact(tmp_path):
    result = run_scenario(scenario(tmp_path, REFRESH))
    assert any(not entry.told for entry in result.decoded)
    assert_same_display(replay(recording_of(result)), result)


def test_newest_decoded_lets_older_frames_go():
    decoded = {3: "a", 5: "b", 9: "c"}
    assert newest_decoded(decoded, 2) == -1
    assert newest_decoded(decoded, 7) == 5
    assert sorted(decoded) == [5, 9]
    assert newest_decoded(decoded, 9) == 9


def test_display_rule_deadline_and_freeze():
    rule = DisplayRule(FixedPlayout(0.2), fps=25.0)
    assert rule.deadline_s(10, 0.0, "") == pytest.approx(0.6)
    assert rule.deadline_s(10, 1.0, "") == 1.0  # never before now
    decoded = {0: None}
    assert rule.show(0, decoded, scheduled=True) == (0, False)
    assert rule.show(1, decoded, scheduled=False) == (0, False)  # a lower frame rate by design
    assert rule.show(2, decoded, scheduled=True) == (0, True)  # frame 2 meant, not decoded
    decoded[2] = None
    assert rule.show(3, decoded, scheduled=False) == (2, False)
    assert rule.show(4, {}, scheduled=True) == (-1, True)
