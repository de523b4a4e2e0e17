"""Playout: the fixed deadline, and the adaptive delay that follows the frames' delay and jitter
but not a one-off burst of late frames."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from pydantic import ValidationError

from uma.config.scenario import AdaptivePlayoutConfig, ReceiverConfig
from uma.sim.playout import MAX_CATCH_UP, AdaptivePlayout, FixedPlayout, make_playout, percentile

FPS = 25.0
REJECT = AdaptivePlayoutConfig(reject_bursts=True)


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
    # Every step is one burst after another within calm_s: followed as the percentile says.
    config = AdaptivePlayoutConfig(min_delay_ms=50, max_delay_ms=1000, reject_bursts=False)
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


def burst(delays_s, start, peak_s, base_s, drain_per_frame_s=0.036):
    """A one-off burst from frame `start`: `peak_s` late, then its queue draining to `base_s`."""
    out = np.array(delays_s, dtype=float)
    for i in range(start, len(out)):
        late_s = peak_s - drain_per_frame_s * (i - start)
        if late_s <= base_s:
            break
        out[i] = late_s
    return out


def test_a_one_off_burst_is_shown_late_but_does_not_hold_the_delay_up():
    # 20 s at 100 ms, then 1.5 s of late frames draining (a handover's queue), then 100 ms.
    delays = burst(np.full(1000, 0.1), 500, 1.5, 0.1)
    kept = drive(AdaptivePlayout(REJECT, initial_delay_s=0.3), delays)
    sized = drive(AdaptivePlayout(AdaptivePlayoutConfig(), initial_delay_s=0.3), delays)
    # The percentile playout rises towards the burst and takes seconds to come down from it.
    assert sized.max() > 1.0 and sized[500 + int(8 * FPS)] > 0.5
    # This one stays within a few frames' rise of where it was, and is back within 3 s.
    assert kept[500:].max() < 0.25
    assert kept[500 + int(3 * FPS) :] == pytest.approx(np.full(500 - int(3 * FPS), 0.12), abs=0.01)


def test_a_lasting_increase_of_delay_is_followed():
    # A handover: a burst draining onto a path 300 ms slower than before, which lasts.
    delays = burst(np.r_[np.full(500, 0.1), np.full(500, 0.4)], 500, 1.5, 0.4)
    trace = drive(AdaptivePlayout(REJECT, initial_delay_s=0.3), delays)
    assert trace[500:].max() < 0.8  # not sized to the burst
    settled = trace[500 + int(4 * FPS) :]
    assert settled == pytest.approx(np.full(settled.size, 0.42), abs=0.01)


def test_a_lasting_increase_of_jitter_is_followed():
    rng = np.random.default_rng(1)
    delays = 0.1 + np.r_[rng.uniform(0.0, 0.02, 500), rng.uniform(0.0, 0.3, 500)]
    trace = drive(AdaptivePlayout(REJECT, initial_delay_s=0.3), delays)
    assert trace[400:500].max() < 0.15
    # Floor + the 95th percentile of the delays above it + 20 ms: about 0.1 + 0.285 + 0.02.
    assert trace[500 + int(4 * FPS) :].min() > 0.35


def test_bursts_in_quick_succession_are_followed_as_the_percentile_says():
    # A second burst 3 s after the first (within calm_s): the link is turbulent, and the delay
    # rises to the second burst as the playout without reject_bursts does.
    delays = burst(burst(np.full(1000, 0.1), 500, 1.5, 0.1), 575, 1.5, 0.1)
    kept = drive(AdaptivePlayout(REJECT, initial_delay_s=0.3), delays)
    assert kept[500:575].max() < 0.25 and kept[575:].max() > 1.0


def test_a_step_of_the_path_is_counted_once():
    # A lasting step from 90 ms to a jittery 400-650 ms path (a handover to a slower one): the
    # first frames after it are far above the old floor, and once the floor has risen they must
    # not count again on top of it. The target then is never above the percentile's.
    rng = np.random.default_rng(2)
    delays = np.r_[np.full(600, 0.09), 0.4 + rng.uniform(0.0, 0.25, 600)]
    kept = drive(AdaptivePlayout(REJECT, initial_delay_s=0.3), delays)
    sized = drive(AdaptivePlayout(AdaptivePlayoutConfig(), initial_delay_s=0.3), delays)
    assert sized[600:].max() < 0.7
    assert kept[600:].max() <= sized[600:].max() + 1e-9


def test_after_a_one_off_burst_the_delays_outside_it_still_set_a_lower_bound():
    # A one-off burst on a jittery path: the frames outside the burst keep their percentile as
    # the lower bound of the target, so once the burst has left the window the delay is where
    # the percentile playout settles, and no lower (the floor + jitter alone may sit below it).
    rng = np.random.default_rng(3)
    delays = burst(0.1 + rng.uniform(0.0, 0.1, 1500), 750, 1.5, 0.2)
    kept = drive(AdaptivePlayout(REJECT, initial_delay_s=0.3), delays)
    sized = drive(AdaptivePlayout(AdaptivePlayoutConfig(), initial_delay_s=0.3), delays)
    assert kept[750:].max() < 0.4 < 1.0 < sized[750:].max()  # not sized to the burst
    late = 750 + int(20 * FPS)  # the burst long gone from both playouts' memory
    assert kept[late:].min() >= sized[late:].min() - 1e-9


def test_no_calm_seen_yet_means_turbulent():
    # The start counts as turbulent: a burst 5 s in is followed as the percentile says.
    delays = burst(np.full(500, 0.1), 125, 1.5, 0.1)
    kept = drive(AdaptivePlayout(REJECT, initial_delay_s=0.3), delays)
    assert kept.max() > 1.0


def test_a_turbulent_link_needs_the_longer_calm_before_a_burst_is_one_off():
    # Bursts at 25 s and 28 s make the link turbulent; one 15 s later (beyond calm_s, within
    # turbulent_calm_s) is followed as the percentile says, one 25 s after that is one-off.
    delays = np.full(2500, 0.1)
    for start_s in (25, 28, 43, 68):
        delays = burst(delays, int(start_s * FPS), 1.5, 0.1)
    kept = drive(AdaptivePlayout(REJECT, initial_delay_s=0.3), delays)
    assert kept[int(25 * FPS) : int(28 * FPS)].max() < 0.25  # the first: calm before it
    assert kept[int(43 * FPS) : int(48 * FPS)].max() > 1.0
    assert kept[int(68 * FPS) :].max() < 0.25


def test_the_floor_window_must_fit_the_window_twice():
    with pytest.raises(ValidationError, match=r"floor_window_s \(1.5\) must be at most half"):
        AdaptivePlayoutConfig(window_s=2.0, floor_window_s=1.5)


def test_a_turbulent_link_needs_at_least_a_calm_links_calm():
    with pytest.raises(ValidationError, match=r"turbulent_calm_s \(5\) must be at least calm_s"):
        AdaptivePlayoutConfig(calm_s=10.0, turbulent_calm_s=5.0)


def test_the_drain_window_must_fit_the_window_twice():
    with pytest.raises(ValidationError, match=r"drain_window_ms \(1500\) must be at most half"):
        AdaptivePlayoutConfig(window_s=2.0, drain_window_ms=1500.0)


def test_holds_when_nothing_arrives():
    playout = AdaptivePlayout(AdaptivePlayoutConfig(), initial_delay_s=0.4)
    assert [playout.delay_s(t) for t in (0.0, 1.0, 5.0)] == [0.4, 0.4, 0.4]


@given(
    st.lists(st.floats(0, 30, allow_nan=False), min_size=1, max_size=60),
    st.floats(0, 100, allow_nan=False),
)
def test_the_percentile_is_numpys_to_the_last_bit(values, q):
    assert percentile(values, q) == float(np.percentile(np.array(values), q))


def test_catch_up_falls_faster_once_the_cause_is_gone():
    # A spike of 1.5 s frames for 1 s on a 0.1 s path: once they leave the 2 s window, the
    # catch-up brings the delay down within about 5 s where 100 ms/s takes over ten.
    delays = np.r_[np.full(250, 0.1), np.full(25, 1.5), np.full(1000, 0.1)]
    slow = drive(AdaptivePlayout(AdaptivePlayoutConfig(), initial_delay_s=0.12), delays)
    fast_config = AdaptivePlayoutConfig(catch_up_s=1.0)
    fast = drive(AdaptivePlayout(fast_config, initial_delay_s=0.12), delays)
    after = 250 + 25 + int(8 * FPS)  # 8 s after the spike's last frame
    assert slow[after] > 0.8
    assert fast[after] < 0.2
    # Never below the target (the frames' 0.1 s plus the margin), never faster than 500 ms/s.
    assert fast[after:].min() >= 0.12 - 1e-9
    assert np.diff(fast).min() >= -MAX_CATCH_UP / FPS - 1e-12
    # Up it goes as before.
    assert fast.max() == pytest.approx(slow.max())


def test_catch_up_off_is_the_fixed_slope():
    delays = np.r_[np.full(100, 0.1), np.full(25, 1.0), np.full(500, 0.1)]
    base = drive(AdaptivePlayout(AdaptivePlayoutConfig(), initial_delay_s=0.3), delays)
    off = drive(AdaptivePlayout(AdaptivePlayoutConfig(catch_up_s=0.0), initial_delay_s=0.3), delays)
    assert np.array_equal(base, off)
    assert np.diff(base).min() >= -0.1 / FPS - 1e-12


def test_catch_up_max_waits_for_every_frame_of_the_window():
    # One frame 1.2 s late among 0.1 s ones: the percentile ignores it, `catch_up_max` does not
    # (the fixed 100 ms/s slope alone until it has left the 2 s window).
    delays = np.full(300, 0.1)
    delays[10] = 1.2  # arrives at 1.6 s, leaves the window at 3.6 s
    plain = AdaptivePlayoutConfig(catch_up_s=1.0)
    strict = AdaptivePlayoutConfig(catch_up_s=1.0, catch_up_max=True)
    fast = drive(AdaptivePlayout(plain, initial_delay_s=1.5), delays)
    held = drive(AdaptivePlayout(strict, initial_delay_s=1.5), delays)
    at_3s = int(3 * FPS)
    assert fast[at_3s] < 0.3
    assert held[at_3s] > 0.5
    assert held[-1] == pytest.approx(0.12, abs=0.01)


def drive_labelled(playout, delays_s, technology_at):
    """As `drive`, telling the playout the receiver's technology at each instant."""
    arrivals = sorted((i / FPS + d, i / FPS) for i, d in enumerate(delays_s))
    out, j = [], 0
    for i in range(len(delays_s)):
        now_s = i / FPS
        while j < len(arrivals) and arrivals[j][0] <= now_s:
            playout.on_decoded(arrivals[j][1], arrivals[j][0])
            j += 1
        out.append(playout.delay_s(now_s, technology_at(now_s)))
    return np.array(out)


def flushed_burst():
    """0.1 s frames; from 4 s the link stalls for 1.5 s and its queue leaves in one burst at
    5.5 s (the frames captured in the stall arrive together), then 0.1 s again."""
    capture_s = np.arange(500) / FPS
    delays = np.full(500, 0.1)
    stalled = (capture_s >= 4.0) & (capture_s < 5.5)
    delays[stalled] = 5.5 - capture_s[stalled]
    return delays


def test_the_rise_follows_the_newest_frames_not_a_flushed_burst():
    delays = flushed_burst()
    plain = drive(AdaptivePlayout(AdaptivePlayoutConfig(), initial_delay_s=0.12), delays)
    bounded_config = AdaptivePlayoutConfig(rise_window_s=0.5)
    bounded = drive(AdaptivePlayout(bounded_config, initial_delay_s=0.12), delays)
    # Without the bound the delay climbs towards the burst's 1.5 s after it was shown and
    # descends at 100 ms/s; with it, it stops when the burst leaves the last 0.5 s.
    assert plain.max() > 1.0
    assert bounded.max() < 0.5
    at_8s = int(8 * FPS)
    assert plain[at_8s] > bounded[at_8s] + 0.5
    # Before the stall both are the same.
    assert np.array_equal(plain[: int(5.5 * FPS)], bounded[: int(5.5 * FPS)])


def test_the_handover_keys_act_only_after_a_named_handover():
    delays = flushed_burst()
    own = AdaptivePlayoutConfig(handover={"for_s": 0.0})
    plain = drive(AdaptivePlayout(own, initial_delay_s=0.12), delays)
    config = AdaptivePlayoutConfig()  # the handover's keys for 20 s after one, by default
    # No named technology (a measured trace): no handover, so exactly the playout's own keys.
    unnamed = drive_labelled(AdaptivePlayout(config, initial_delay_s=0.12), delays, lambda t: "")
    assert np.array_equal(unnamed, plain)
    # The same technology throughout: no handover either.
    same = drive_labelled(AdaptivePlayout(config, initial_delay_s=0.12), delays, lambda t: "3G")
    assert np.array_equal(same, plain)
    # A handover at 4 s (3G to GPRS), the stall it brings flushed at 5.5 s: with the handover's
    # keys (a 1-s window, a fast descent, the catch-up) the delay leaves the spike within 2.5 s,
    # where the playout's own keys still hold it above 1 s.
    handover = drive_labelled(
        AdaptivePlayout(config, initial_delay_s=0.12), delays, lambda t: "3G" if t < 4.0 else "GPRS"
    )
    assert np.array_equal(handover[: int(4 * FPS)], plain[: int(4 * FPS)])
    at_8s = int(8 * FPS)
    assert plain.max() > 1.0 and plain[at_8s] > 1.0
    # ... down to the newest frames' 0.1 s plus the handover's wider margin (100 ms).
    assert handover[at_8s] == pytest.approx(0.1 + 0.1)


def test_the_handover_keys_end_after_for_s():
    # A handover at 1 s, the stall at 4 s: with a 2-s window the playout follows its own keys
    # again by the stall, and climbs after the burst as the plain playout does.
    delays = flushed_burst()
    config = AdaptivePlayoutConfig(handover={"for_s": 2.0})
    late = drive_labelled(
        AdaptivePlayout(config, initial_delay_s=0.12), delays, lambda t: "3G" if t < 1.0 else "GPRS"
    )
    assert late.max() > 1.0


def test_the_handover_keys_are_checked_as_the_playouts_own():
    with pytest.raises(ValueError, match="handover"):
        AdaptivePlayoutConfig(handover={"window_s": 0.3})  # the drain window needs 0.5 s
    during = AdaptivePlayoutConfig().during_handover()
    assert (during.margin_ms, during.window_s, during.catch_up_s) == (100.0, 1.0, 0.5)
