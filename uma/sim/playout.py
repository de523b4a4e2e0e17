"""When the receiver shows each frame: a fixed playout delay, or one that follows the network.

Units: seconds. Pure (no SimPy): the display process asks `delay_s(now_s)` before each frame's
display instant (capture time + delay), and the receiver tells `on_decoded` of every frame it
decodes.

`AdaptivePlayout` behaves as WebRTC's video jitter buffer does in outline: a target delay from
the recent frames' capture-to-decoded delays (a high percentile over a time window, plus a
margin, within bounds), which the current delay approaches at a bounded slope, so a change
plays as slow or fast motion rather than a jump: down by at most `max_decrease_ms_per_s`
(WebRTC's VCMTiming: 100 ms per second), up by at most `max_increase_ms_per_s`. WebRTC also
lets a late frame raise the delay at once by its lateness; here it may not (on cellular traces
one frame queued through an outage would set seconds of delay in one step), so the delay stays
smooth. With no frame decoded within the window the delay holds.

With `reject_bursts` (off by default: measured in docs/rate-control.md, section `rc7`) the
target, as WebRTC separates a change of the path's delay (its timestamp extrapolator, which
moves to a new offset only when frames keep arriving off it) from jitter (its jitter estimator,
which clamps a frame delay beyond a number of standard deviations as an outlier): the path's
*floor* is the least delay of the frames decoded in the last `floor_window_s` (it follows a
lasting change of the path's delay within that time, and any fall at once), the *jitter* the
`percentile` of the window's delays above the floor each met. A frame later than the floor by
more than `outlier_min_ms` and `outlier_jitters` jitters starts a *burst* (late frames closer
than `burst_gap_ms` are one). A burst that comes `calm_s` after the last late frame or later is
one-off: until the next burst the target is floor + jitter + margin, and the delay does not
rise while the floor falls (the burst's own queue draining). A burst sooner than that marks the
link as turbulent: until the next burst the target is the window's percentile of the delays
themselves plus the margin (the playout without `reject_bursts`), so repeated late bursts hold
the delay up as before.
"""

from __future__ import annotations

import math
from collections import deque

from uma.config.scenario import AdaptivePlayoutConfig, ReceiverConfig

__all__ = ["FixedPlayout", "AdaptivePlayout", "make_playout", "percentile"]


class FixedPlayout:
    """Every frame at its capture time plus one fixed delay."""

    def __init__(self, delay_s: float) -> None:
        self._delay_s = delay_s

    def on_decoded(self, capture_s: float, arrival_s: float) -> None:
        pass

    def delay_s(self, now_s: float) -> float:
        return self._delay_s


class AdaptivePlayout:
    """A playout delay that tracks the frames' delay and jitter, bounded and rate-limited; with
    `reject_bursts`, a one-off burst of late frames on a calm link does not hold it up."""

    def __init__(self, config: AdaptivePlayoutConfig, *, initial_delay_s: float) -> None:
        self.config = config
        self.min_s = config.min_delay_ms / 1000.0
        self.max_s = max(self.min_s, config.max_delay_ms / 1000.0)
        self.current_s = min(max(initial_delay_s, self.min_s), self.max_s)
        # (arrival_s, delay_s, delay above the floor it met) of the frames within `window_s`
        self._samples: deque[tuple[float, float, float]] = deque()
        # (arrival_s, delay_s) of the frames within `floor_window_s` of the last one decoded
        self._recent: deque[tuple[float, float]] = deque()
        self._last_late_s = -math.inf  # arrival of the last frame late beyond the jitter
        self.turbulent = not config.reject_bursts
        self._last_s: float | None = None

    def _expire(self, now_s: float) -> None:
        window_start_s = now_s - self.config.window_s
        while self._samples and self._samples[0][0] < window_start_s:
            self._samples.popleft()

    def jitter_s(self) -> float:
        """The window's `percentile` of the delays above the floor each frame met (0 if none)."""
        if not self._samples:
            return 0.0
        return percentile([above for _, _, above in self._samples], self.config.percentile)

    def target_s(self, now_s: float) -> float | None:
        """The delay the recent frames ask for; None when no frame arrived within the window."""
        self._expire(now_s)
        if not self._samples:
            return None
        if self.turbulent:
            wanted = percentile([d for _, d, _ in self._samples], self.config.percentile)
        else:
            wanted = self.floor_s() + self.jitter_s()
        wanted += self.config.margin_ms / 1000.0
        return min(max(wanted, self.min_s), self.max_s)

    def floor_s(self) -> float:
        """The path's floor: the least delay within `floor_window_s` of the last frame decoded
        (a silence keeps it); 0 before the first frame."""
        return min((d for _, d in self._recent), default=0.0)

    def on_decoded(self, capture_s: float, arrival_s: float) -> None:
        delay = arrival_s - capture_s
        self._expire(arrival_s)
        if not self.config.reject_bursts:  # the percentile alone: no floor to keep
            self._samples.append((arrival_s, delay, 0.0))
            return
        if self._recent:
            self._judge(delay, arrival_s)
        floor_start_s = arrival_s - self.config.floor_window_s
        while self._recent and self._recent[0][0] < floor_start_s:
            self._recent.popleft()
        self._recent.append((arrival_s, delay))
        self._samples.append((arrival_s, delay, delay - self.floor_s()))

    def _judge(self, delay: float, arrival_s: float) -> None:
        """A frame late beyond the jitter: the start of a burst, one-off after a calm spell."""
        limit_s = max(
            self.config.outlier_min_ms / 1000.0, self.config.outlier_jitters * self.jitter_s()
        )
        if delay - self.floor_s() <= limit_s:
            return
        since_s = arrival_s - self._last_late_s
        if since_s > self.config.burst_gap_ms / 1000.0:
            self.turbulent = since_s < self.config.calm_s
        self._last_late_s = arrival_s

    def draining(self, now_s: float) -> bool:
        """Whether the floor fell by `drain_drop_ms` within the last `drain_window_ms`."""
        window_s = self.config.drain_window_ms / 1000.0
        newer = [d for a, d, _ in self._samples if a >= now_s - window_s]
        older = [d for a, d, _ in self._samples if now_s - 2 * window_s <= a < now_s - window_s]
        drop_s = self.config.drain_drop_ms / 1000.0
        return bool(newer and older) and min(newer) < min(older) - drop_s

    def delay_s(self, now_s: float) -> float:
        elapsed_s = 0.0 if self._last_s is None else max(0.0, now_s - self._last_s)
        self._last_s = now_s
        target = self.target_s(now_s)
        if target is not None:
            up_s = self.config.max_increase_ms_per_s / 1000.0 * elapsed_s
            if not self.turbulent and self.draining(now_s):
                up_s = 0.0
            down_s = self.config.max_decrease_ms_per_s / 1000.0 * elapsed_s
            self.current_s += min(max(target - self.current_s, -down_s), up_s)
        return self.current_s


def percentile(values: list[float], q: float) -> float:
    """The `q`-th percentile of `values` (non-empty), exactly as `numpy.percentile`'s default
    (linear) method computes it, without its per-call cost on a few dozen samples."""
    ordered = sorted(values)
    virtual = (len(ordered) - 1) * (q / 100.0)
    if virtual >= len(ordered) - 1:
        return ordered[-1]
    below = math.floor(virtual)
    low, high = ordered[below], ordered[below + 1]
    gamma, diff = virtual - below, high - low
    # numpy's _lerp: from the nearer end, so the result stays within [low, high].
    return high - diff * (1 - gamma) if gamma >= 0.5 else low + diff * gamma


def make_playout(config: ReceiverConfig) -> FixedPlayout | AdaptivePlayout:
    """The playout the scenario's `receiver.playout` names."""
    initial_s = config.playout_delay_ms / 1000.0
    if config.playout == "adaptive":
        return AdaptivePlayout(config.adaptive, initial_delay_s=initial_s)
    return FixedPlayout(initial_s)
