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
    """A playout delay that tracks the frames' delay and jitter, bounded and rate-limited."""

    def __init__(self, config: AdaptivePlayoutConfig, *, initial_delay_s: float) -> None:
        self.config = config
        self.min_s = config.min_delay_ms / 1000.0
        self.max_s = max(self.min_s, config.max_delay_ms / 1000.0)
        self.current_s = min(max(initial_delay_s, self.min_s), self.max_s)
        self._samples: deque[tuple[float, float]] = deque()  # (arrival_s, delay_s)
        self._last_s: float | None = None

    def target_s(self, now_s: float) -> float | None:
        """The delay the recent frames ask for; None when no frame arrived within the window."""
        window_start_s = now_s - self.config.window_s
        while self._samples and self._samples[0][0] < window_start_s:
            self._samples.popleft()
        if not self._samples:
            return None
        wanted = percentile([d for _, d in self._samples], self.config.percentile)
        wanted += self.config.margin_ms / 1000.0
        return min(max(wanted, self.min_s), self.max_s)

    def on_decoded(self, capture_s: float, arrival_s: float) -> None:
        self._samples.append((arrival_s, arrival_s - capture_s))

    def delay_s(self, now_s: float) -> float:
        elapsed_s = 0.0 if self._last_s is None else max(0.0, now_s - self._last_s)
        self._last_s = now_s
        target = self.target_s(now_s)
        if target is not None:
            up_s = self.config.max_increase_ms_per_s / 1000.0 * elapsed_s
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
