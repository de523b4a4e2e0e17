"""Playout: the fixed deadline, and the adaptive delay that follows the frames' delay and jitter."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from uma.config.scenario import AdaptivePlayoutConfig, ReceiverConfig
from uma.sim.playout import AdaptivePlayout, FixedPlayout, make_playout, percentile

FPS = 25.0


def drive(playout, delays_s):
    """Frames captured at 25 fps arrive after `delays_s`; ask the delay at each capture instant."""
    arrivals = [(i / FPS + d, i / FPS) for i, d in enumerate(delays_s)]
    arrivals.sort()
    out = []
    j = 0
    for i in range(len(delays_s)):
        now_s = i / FPS
        while j < len(arrivals) and arrivals[j][0] <= now_s:
            playout.on_decoded(arrivals[j][1], arrivals[j][0])
            j += 1
        out.append(playout.delay_s(now_s))
    return np.array(out)


def test_make_playout_by_name():
    assert isinstance(make_playout(ReceiverConfig()), FixedPlayout)
    assert isinstance(make_playout(ReceiverConfig(playout="adaptive")), AdaptivePlayout)
    assert make_playout(ReceiverConfig(playout_delay_ms=250)).delay_s(3.0) == 0.25


def test_tracks_delay_and_jitter_within_its_bounds():
    rng = np.random.default_rng(0)
    delays = 0.1 + rng.uniform(0.0, 0.06, 1000)  # 100 ms base, 60 ms of jitter
    config = AdaptivePlayoutConfig()
    playout = AdaptivePlayout(config, initial_delay_s=0.3)
    trace = drive(playout, delays)
    settled = trace[500:]
    # Near the 95th percentile of the delays plus the 20 ms margin, and steady there.
    assert settled.min() >= 0.14 and settled.max() <= 0.2
    assert settled.max() - settled.min() < 0.03
    # It came down from 300 ms no faster than 100 ms per second.
    steps = np.diff(trace)
    assert steps.min() >= -0.1 / FPS - 1e-12
    assert steps.max() <= 0.5 / FPS + 1e-12


def test_follows_a_step_smoothly_and_stays_bounded():
    config = AdaptivePlayoutConfig(min_delay_ms=50, max_delay_ms=1000)
    delays = np.r_[np.full(250, 0.08), np.full(500, 0.6), np.full(500, 2.5), np.full(750, 0.08)]
    trace = drive(AdaptivePlayout(config, initial_delay_s=0.3), delays)
    steps = np.diff(trace)
    assert steps.max() <= 0.5 / FPS + 1e-12 and steps.min() >= -0.1 / FPS - 1e-12
    assert trace.min() >= 0.05 and trace.max() <= 1.0 + 1e-12
    # Up 520 ms at 500 ms/s: 1.04 s, after the first late frame arrives 0.6 s into the step.
    after_up = trace[250 + int(1.7 * FPS) : 750]
    assert after_up == pytest.approx(np.full(after_up.size, 0.62), abs=0.02)
    assert trace[1249] == pytest.approx(1.0)  # capped at max_delay_ms
    # Down at 100 ms/s once the 2.5 s frames have arrived (2.5 s) and left the 2 s window:
    # about 0.45 s ten seconds after the drop, at the new target 20 s later.
    assert 0.4 < trace[1250 + int(10 * FPS)] < 0.5
    assert trace[-1] == pytest.approx(0.1, abs=0.01)


def test_holds_when_nothing_arrives():
    playout = AdaptivePlayout(AdaptivePlayoutConfig(), initial_delay_s=0.4)
    assert [playout.delay_s(t) for t in (0.0, 1.0, 5.0)] == [0.4, 0.4, 0.4]


@given(
    st.lists(st.floats(0, 30, allow_nan=False), min_size=1, max_size=60),
    st.floats(0, 100, allow_nan=False),
)
def test_the_percentile_is_numpys_to_the_last_bit(values, q):
    assert percentile(values, q) == float(np.percentile(np.array(values), q))
