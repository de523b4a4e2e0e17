"""GCC's delay-based detector: inter-arrival groups, the trendline, the adaptive threshold.

Units: ms, bits. Written from the published description (IETF draft-ietf-rmcat-gcc-02,
sections 5.2-5.4, and libwebrtc's documented trendline design), not from another project's code:

- **Groups** (draft 5.2): packets sent within `burst_ms` (5 ms) of a group's first packet form
  one group; a packet that arrives within `burst_ms` of the previous one and whose delay
  variation is negative (it caught up in a burst) joins the group too, as long as the group
  spans at most `max_burst_ms` (100 ms). Each completed group after the first yields a delta:
  send-time and arrival-time differences of the groups' last packets.
- **Trendline** (libwebrtc): the delay variation accumulates, is smoothed exponentially
  (coefficient 0.9), and the least-squares slope of the smoothed delay against arrival time
  over the last `window` (20) groups, times `min(deltas, 60) * gain` (gain 4), is the trend m.
- **Adaptive threshold** (draft 5.4; libwebrtc's gains for the trendline): gamma follows |m|,
  `gamma += dt * k * (|m| - gamma)` with k = k_u (0.0087) when |m| > gamma, k_d (0.039) when
  below, dt capped at 100 ms, no update when |m| > gamma + 15, gamma kept in [6, 600].
- **Over-use** (draft 5.5): m > gamma for more than 10 ms, over at least two groups, with m not
  falling; under-use: m < -gamma; normal otherwise.
"""

from __future__ import annotations

import enum
from collections import deque
from dataclasses import dataclass

import numpy as np

__all__ = [
    "Usage",
    "GroupDelta",
    "InterArrival",
    "Trendline",
    "AdaptiveThreshold",
    "OveruseDetector",
]


class Usage(enum.Enum):
    NORMAL = "normal"
    OVER = "over"
    UNDER = "under"


@dataclass(frozen=True)
class GroupDelta:
    send_delta_ms: float
    arrival_delta_ms: float
    arrival_ms: float  # the completed group's last arrival


@dataclass
class _Group:
    first_send_ms: float
    last_send_ms: float
    first_arrival_ms: float
    last_arrival_ms: float


class InterArrival:
    """Packets in, a `GroupDelta` out each time a group completes (None otherwise)."""

    def __init__(self, *, burst_ms: float = 5.0, max_burst_ms: float = 100.0) -> None:
        self.burst_ms, self.max_burst_ms = burst_ms, max_burst_ms
        self._current: _Group | None = None
        self._previous: _Group | None = None

    def on_packet(self, send_ms: float, arrival_ms: float) -> GroupDelta | None:
        current = self._current
        if current is None:
            self._current = _Group(send_ms, send_ms, arrival_ms, arrival_ms)
            return None
        if send_ms < current.first_send_ms:
            return None  # reordered from an older group: ignored
        if self._belongs(current, send_ms, arrival_ms):
            current.last_send_ms = max(current.last_send_ms, send_ms)
            current.last_arrival_ms = max(current.last_arrival_ms, arrival_ms)
            return None
        delta = None
        if self._previous is not None:
            delta = GroupDelta(
                current.last_send_ms - self._previous.last_send_ms,
                current.last_arrival_ms - self._previous.last_arrival_ms,
                current.last_arrival_ms,
            )
        self._previous = current
        self._current = _Group(send_ms, send_ms, arrival_ms, arrival_ms)
        return delta

    def _belongs(self, group: _Group, send_ms: float, arrival_ms: float) -> bool:
        if send_ms - group.first_send_ms <= self.burst_ms:
            return True
        arrival_gap = arrival_ms - group.last_arrival_ms
        variation = arrival_gap - (send_ms - group.last_send_ms)
        in_burst = arrival_gap < self.burst_ms and variation < 0
        return in_burst and arrival_ms - group.first_arrival_ms < self.max_burst_ms


class Trendline:
    """Group deltas in, the modified trend m (ms) out."""

    def __init__(
        self, *, window: int = 20, smoothing: float = 0.9, gain: float = 4.0, max_deltas: int = 60
    ) -> None:
        self.window, self.smoothing, self.gain, self.max_deltas = (
            window,
            smoothing,
            gain,
            max_deltas,
        )
        self._accumulated_ms = 0.0
        self._smoothed_ms = 0.0
        self._first_arrival_ms: float | None = None
        self._points: deque[tuple[float, float]] = deque(maxlen=window)
        self.deltas = 0
        self.trend = 0.0

    def update(self, delta: GroupDelta) -> float:
        self.deltas += 1
        self._accumulated_ms += delta.arrival_delta_ms - delta.send_delta_ms
        self._smoothed_ms = (
            self.smoothing * self._smoothed_ms + (1.0 - self.smoothing) * self._accumulated_ms
        )
        if self._first_arrival_ms is None:
            self._first_arrival_ms = delta.arrival_ms
        self._points.append((delta.arrival_ms - self._first_arrival_ms, self._smoothed_ms))
        if len(self._points) == self.window:
            self.trend = least_squares_slope(self._points)
        return min(self.deltas, self.max_deltas) * self.trend * self.gain


def least_squares_slope(points) -> float:
    """Slope of y on x; 0 when every x is the same."""
    x, y = (np.asarray(column, dtype=float) for column in zip(*points, strict=True))
    dx = x - x.mean()
    denominator = float(dx @ dx)
    return float(dx @ (y - y.mean())) / denominator if denominator > 0 else 0.0


class AdaptiveThreshold:
    """gamma, following |m|: up with k_u, down with k_d, in [min_ms, max_ms]."""

    def __init__(
        self,
        *,
        initial_ms: float = 12.5,
        k_up: float = 0.0087,
        k_down: float = 0.039,
        max_offset_ms: float = 15.0,
        max_step_ms: float = 100.0,
        min_ms: float = 6.0,
        max_ms: float = 600.0,
    ) -> None:
        self.value_ms = initial_ms
        self.k_up, self.k_down = k_up, k_down
        self.max_offset_ms, self.max_step_ms = max_offset_ms, max_step_ms
        self.min_ms, self.max_ms = min_ms, max_ms
        self._last_ms: float | None = None

    def update(self, trend: float, now_ms: float) -> float:
        """Move gamma towards |trend| for the time since the last update; the new gamma."""
        if self._last_ms is None:
            self._last_ms = now_ms
        if abs(trend) > self.value_ms + self.max_offset_ms:
            self._last_ms = now_ms  # a spike: do not let it drag the threshold
            return self.value_ms
        k = self.k_down if abs(trend) < self.value_ms else self.k_up
        step_ms = min(now_ms - self._last_ms, self.max_step_ms)
        self.value_ms += k * (abs(trend) - self.value_ms) * step_ms
        self.value_ms = min(max(self.value_ms, self.min_ms), self.max_ms)
        self._last_ms = now_ms
        return self.value_ms


class OveruseDetector:
    """m and the send delta in, the usage signal out; the threshold adapts as it goes."""

    def __init__(
        self, threshold: AdaptiveThreshold | None = None, *, overuse_ms: float = 10.0
    ) -> None:
        self.threshold = threshold or AdaptiveThreshold()
        self.overuse_ms = overuse_ms
        self.state = Usage.NORMAL
        self._time_over_ms = -1.0
        self._count = 0
        self._previous_trend = 0.0

    def detect(self, trend: float, send_delta_ms: float, now_ms: float) -> Usage:
        gamma = self.threshold.value_ms
        if trend > gamma:
            if self._time_over_ms < 0:
                self._time_over_ms = send_delta_ms / 2.0  # assume half the gap was over
            else:
                self._time_over_ms += send_delta_ms
            self._count += 1
            if (
                self._time_over_ms > self.overuse_ms
                and self._count > 1
                and trend >= self._previous_trend
            ):
                self._time_over_ms, self._count = 0.0, 0
                self.state = Usage.OVER
        elif trend < -gamma:
            self._time_over_ms, self._count = -1.0, 0
            self.state = Usage.UNDER
        else:
            self._time_over_ms, self._count = -1.0, 0
            self.state = Usage.NORMAL
        self._previous_trend = trend
        self.threshold.update(trend, now_ms)
        return self.state
