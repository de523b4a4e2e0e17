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
smooth. With no frame decoded within the window the delay holds. With `catch_up_s` the delay
falls faster while far above its target (the recent frames no longer ask for it: a queue
drained, a handover's backlog shown): by its excess over the target per `catch_up_s`, never
more than `MAX_CATCH_UP` (500 ms a second, so display instants never go back in time); with
`catch_up_max`, towards the highest delay of the window plus the margin instead of the target.
With `rise_window_s` the delay rises only towards what the newest frames ask for (the highest
delay of those decoded in the last `rise_window_s`, plus the margin): frames queued through an
outage arrive in one burst and are shown at once, late whatever the delay; rising to the window's
percentile afterwards delays only the frames behind them. Within `handover.for_s` of a handover
(`delay_s`'s `technology` changing between two named ones) the playout follows the handover's
keys instead of its own (`AdaptivePlayoutConfig.during_handover`): a stall of known cause, over
once the new link carries the queue, is left fast, and the new technology's jitter gets a wider
margin; a link with no named technologies never has one.

With `reject_bursts` (off by default: measured in docs/rate-control.md, sections `rc8` and `rc7`)
the target, as WebRTC separates a change of the path's delay (its timestamp extrapolator, which
moves to a new offset only when frames keep arriving off it) from jitter (its jitter estimator,
which clamps a frame delay beyond a number of standard deviations as an outlier): the path's
*floor* is the least delay of the frames decoded in the last `floor_window_s` (it follows a
lasting change of the path's delay within that time, and any fall at once), the *jitter* the
`percentile` of the window's delays above the higher of the floor each frame met and the floor
now (so a step of the path, first measured against the old floor, is not counted again once the
floor has risen). A frame later than the floor by more than `outlier_min_ms` and
`outlier_jitters` jitters starts a *burst* (late frames closer than `burst_gap_ms` are one). A
burst that comes `calm_s` after the last late frame or later is one-off (`turbulent_calm_s` if
the link was turbulent; the start counts as a late frame on a turbulent link, so calm must be
seen first): until the next burst the target is the higher of floor + jitter and the percentile
of the delays of the frames outside a burst's *episode*, plus the margin, and the delay does not
rise while the floor falls (the burst's own queue draining). An episode runs from a burst's first
late frame (taking back the frames of the floor window before it: the floor lags a burst by that
long, so its first frames may not look late) until, two floor windows on at the least and
`burst_gap_ms` after its last late frame, the floor stops falling. A burst sooner than `calm_s`
marks the link as turbulent: until the next burst the target is the window's percentile of the
delays themselves plus the margin (the playout without `reject_bursts`), so repeated late bursts
hold the delay up as before.
"""

from __future__ import annotations

import math
from collections import deque

from uma.config.scenario import AdaptivePlayoutConfig, ReceiverConfig

__all__ = ["FixedPlayout", "AdaptivePlayout", "make_playout", "percentile", "MAX_CATCH_UP"]

# The fastest the catch-up lowers the delay: seconds of delay per second.
MAX_CATCH_UP = 0.5


class FixedPlayout:
    """Every frame at its capture time plus one fixed delay."""

    def __init__(self, delay_s: float) -> None:
        self._delay_s = delay_s

    def on_decoded(self, capture_s: float, arrival_s: float) -> None:
        pass

    def delay_s(self, now_s: float, technology: str = "") -> float:
        return self._delay_s


class AdaptivePlayout:
    """A playout delay that tracks the frames' delay and jitter, bounded and rate-limited; with
    `reject_bursts`, a one-off burst of late frames on a calm link does not hold it up."""

    def __init__(self, config: AdaptivePlayoutConfig, *, initial_delay_s: float) -> None:
        self.config = config
        self.min_s = config.min_delay_ms / 1000.0
        self.max_s = max(self.min_s, config.max_delay_ms / 1000.0)
        self.current_s = min(max(initial_delay_s, self.min_s), self.max_s)
        # (arrival_s, delay_s, the floor it met) of the frames within `window_s`
        self._samples: deque[tuple[float, float, float]] = deque()
        # (arrival_s, delay_s) of the frames within `floor_window_s` of the last one decoded
        self._recent: deque[tuple[float, float]] = deque()
        # (arrival_s, delay_s) of the frames within `window_s` outside a burst's episode
        self._clean: deque[tuple[float, float]] = deque()
        self._last_late_s = -math.inf  # arrival of the last frame late beyond the jitter
        self._episode_s: float | None = None  # arrival of the first late frame of a burst
        # Until a calm spell is seen, the link counts as turbulent (the start included).
        self.turbulent = True
        self._last_s: float | None = None
        self._technology = ""  # the receiver's technology at the last display instant
        self._handover_s = -math.inf  # when it last changed between two named technologies
        # The keys it follows away from a handover, and within `handover.for_s` of one.
        self._own = config
        self._after_handover = config.during_handover() if config.handover.for_s > 0 else None

    def _expire(self, now_s: float) -> None:
        window_start_s = now_s - self.config.window_s
        for window in (self._samples, self._clean):
            while window and window[0][0] < window_start_s:
                window.popleft()

    def jitter_s(self) -> float:
        """The window's `percentile` of the delays above the floor: each frame's delay above the
        higher of the floor it met and the floor now (a step of the path is counted once)."""
        if not self._samples:
            return 0.0
        floor = self.floor_s()
        above = [max(0.0, d - max(met, floor)) for _, d, met in self._samples]
        return percentile(above, self.config.percentile)

    def target_s(self, now_s: float) -> float | None:
        """The delay the recent frames ask for; None when no frame arrived within the window."""
        self._expire(now_s)
        if not self._samples:
            return None
        if self.turbulent:
            wanted = percentile([d for _, d, _ in self._samples], self.config.percentile)
        else:
            wanted = self.floor_s() + self.jitter_s()
            if self._clean:
                clean = percentile([d for _, d in self._clean], self.config.percentile)
                wanted = max(wanted, clean)
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
        if not self._recent and self._last_late_s == -math.inf:
            self._last_late_s = arrival_s  # the first frame: no calm seen before it
        late = bool(self._recent) and self._judge(delay, arrival_s)
        floor_start_s = arrival_s - self.config.floor_window_s
        while self._recent and self._recent[0][0] < floor_start_s:
            self._recent.popleft()
        self._recent.append((arrival_s, delay))
        self._samples.append((arrival_s, delay, self.floor_s()))
        self._follow_episode(late, arrival_s)
        if self._episode_s is None:
            self._clean.append((arrival_s, delay))

    def _judge(self, delay: float, arrival_s: float) -> bool:
        """Whether a frame is late beyond the jitter; the first of a burst says whether the link
        is turbulent (`calm_s` since the last late frame, `turbulent_calm_s` if it was)."""
        limit_s = max(
            self.config.outlier_min_ms / 1000.0, self.config.outlier_jitters * self.jitter_s()
        )
        if delay - self.floor_s() <= limit_s:
            return False
        since_s = arrival_s - self._last_late_s
        if since_s > self.config.burst_gap_ms / 1000.0:
            calm_s = self.config.turbulent_calm_s if self.turbulent else self.config.calm_s
            self.turbulent = since_s < calm_s
        self._last_late_s = arrival_s
        return True

    def _follow_episode(self, late: bool, arrival_s: float) -> None:
        """A burst's episode: from its first late frame (taking back the frames of the floor
        window before it, which the lagging floor may not have judged late) until, at least two
        floor windows on and `burst_gap_ms` after its last late frame, the floor stops falling."""
        if late:
            if self._episode_s is None:
                self._episode_s = arrival_s
                start_s = arrival_s - self.config.floor_window_s
                while self._clean and self._clean[-1][0] >= start_s:
                    self._clean.pop()
            return
        if (
            self._episode_s is not None
            and arrival_s - self._episode_s >= 2 * self.config.floor_window_s
            and arrival_s - self._last_late_s > self.config.burst_gap_ms / 1000.0
            and not self.falling(arrival_s)
            and not self.draining(arrival_s)
        ):
            self._episode_s = None

    def _fell(self, now_s: float, window_s: float) -> bool:
        """Whether the least delay of the last `window_s` is `drain_drop_ms` below the least of
        the `window_s` before it."""
        newer = [d for a, d, _ in self._samples if a >= now_s - window_s]
        older = [d for a, d, _ in self._samples if now_s - 2 * window_s <= a < now_s - window_s]
        drop_s = self.config.drain_drop_ms / 1000.0
        return bool(newer and older) and min(newer) < min(older) - drop_s

    def draining(self, now_s: float) -> bool:
        """Whether the floor fell by `drain_drop_ms` within the last `drain_window_ms`."""
        return self._fell(now_s, self.config.drain_window_ms / 1000.0)

    def falling(self, now_s: float) -> bool:
        """Whether the floor fell by `drain_drop_ms` from one `floor_window_s` to the next."""
        return self._fell(now_s, self.config.floor_window_s)

    def delay_s(self, now_s: float, technology: str = "") -> float:
        """The playout delay at `now_s`; `technology`: the receiver's link then ("": unnamed)."""
        elapsed_s = 0.0 if self._last_s is None else max(0.0, now_s - self._last_s)
        self._last_s = now_s
        self._note_technology(now_s, technology)
        self._follow_handover(now_s)
        target = self.target_s(now_s)
        if target is not None:
            up_s = self.config.max_increase_ms_per_s / 1000.0 * elapsed_s
            if self.config.rise_window_s > 0.0:
                recent_s = self._highest_s(now_s - self.config.rise_window_s)
                up_s = min(up_s, max(0.0, recent_s - self.current_s))
            if not self.turbulent and self.draining(now_s):
                up_s = 0.0
            down_s = self.config.max_decrease_ms_per_s / 1000.0 * elapsed_s
            if self.config.catch_up_s > 0.0:
                excess_s = self.current_s - self._catch_up_floor_s(target)
                slope = min(excess_s / self.config.catch_up_s, MAX_CATCH_UP)
                down_s = max(down_s, slope * elapsed_s)
            self.current_s += min(max(target - self.current_s, -down_s), up_s)
        return self.current_s

    def _highest_s(self, since_s: float = -math.inf) -> float:
        """The highest delay of the window's frames decoded since `since_s`, plus the margin
        (the margin alone when none was): what those frames ask for."""
        delays = [d for a, d, _ in self._samples if a >= since_s]
        return max(delays, default=0.0) + self.config.margin_ms / 1000.0

    def _note_technology(self, now_s: float, technology: str) -> None:
        """A change between two named technologies is a handover (unnamed links have none)."""
        if technology and self._technology and technology != self._technology:
            self._handover_s = now_s
        if technology:
            self._technology = technology

    def _follow_handover(self, now_s: float) -> None:
        """Follow the handover's keys within `handover.for_s` of a handover, else its own."""
        after = self._after_handover
        near = after is not None and now_s - self._handover_s <= self._own.handover.for_s
        self.config = after if near else self._own

    def _catch_up_floor_s(self, target_s: float) -> float:
        """What the catch-up falls towards: the target, and never below the highest delay of
        the window's frames plus the margin (the cause must be gone from every one of them)."""
        return max(target_s, self._highest_s()) if self.config.catch_up_max else target_s


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
