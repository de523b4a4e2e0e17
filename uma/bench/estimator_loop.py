"""WebRTC's estimator in a closed loop over one FIFO bottleneck: convergence and step response.

Units: seconds, kbit/s, bits. Pure Python, no SimPy, no codec: a sender that sends, at each
frame instant, one frame's worth of its current rate (cut into 1200-byte payloads with 40-byte
headers, all stamped with the same send time, as uma's engine does), over a link of the given
capacity with a propagation delay; the receiver feeds every packet to `RembEstimator`, and the
sender takes its REMB with the feedback delay. What `uma bench salsify` and the tests measure
the estimator's convergence and back-off with.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["LoopTrace", "closed_loop", "step_response"]

PAYLOAD_BYTES = 1200
HEADER_BYTES = 40


@dataclass(frozen=True)
class LoopTrace:
    """Per frame instant: time, the sender's rate, the capacity, the newest packet's delay."""

    time_s: np.ndarray
    rate_kbps: np.ndarray
    capacity_kbps: np.ndarray
    delay_s: np.ndarray


def closed_loop(
    capacity_kbps: Callable[[float], float],
    *,
    duration_s: float,
    fps: float = 25.0,
    initial_kbps: float = 300.0,
    delay_s: float = 0.02,
    max_burst: bool = True,
) -> LoopTrace:
    """Run the loop; feedback reaches the sender one propagation delay after the packet."""
    from uma.engine.webrtc import RembEstimator

    estimator = RembEstimator(max_burst=max_burst)
    rate = initial_kbps
    busy_s = 0.0
    pending: list[tuple[float, float]] = []  # (time the sender learns it, estimate)
    rows = []
    for index in range(int(round(duration_s * fps))):
        now_s = index / fps
        while pending and pending[0][0] <= now_s:
            rate = pending.pop(0)[1]
        frame_bits = rate * 1000.0 / fps
        packets = max(1, math.ceil(frame_bits / 8 / PAYLOAD_BYTES))
        arrive_s = now_s
        for _ in range(packets):
            size_bits = int(frame_bits / packets) + 8 * HEADER_BYTES
            busy_s = max(busy_s, now_s) + size_bits / (capacity_kbps(now_s) * 1000.0)
            arrive_s = busy_s + delay_s
            before = estimator.updates
            estimator.on_packet(arrival_s=arrive_s, sent_s=now_s, size_bits=size_bits)
            if estimator.updates != before:
                pending.append((arrive_s + delay_s, estimator.estimate_kbps))
        rows.append((now_s, rate, capacity_kbps(now_s), arrive_s - now_s))
    time_s, rate_kbps, cap_kbps, delays_s = (np.array(col) for col in zip(*rows, strict=True))
    return LoopTrace(time_s, rate_kbps, cap_kbps, delays_s)


def step_response(
    *,
    high_kbps: float = 1000.0,
    low_kbps: float = 300.0,
    step_s: float = 40.0,
    after_s: float = 20.0,
) -> dict[str, float | None]:
    """Capacity `high_kbps` until `step_s`, then `low_kbps`: how the estimate follows.

    `converged_kbps`: the median rate over the 10 s before the step; `backoff_s`: from the step
    until the rate is first at or below the new capacity (None if never); `settled_kbps`: the
    median rate over the last 10 s; `peak_delay_ms`: the worst packet delay after the step.
    """
    trace = closed_loop(
        lambda t: high_kbps if t < step_s else low_kbps, duration_s=step_s + after_s
    )
    before = (trace.time_s >= step_s - 10.0) & (trace.time_s < step_s)
    after = trace.time_s >= step_s
    below = np.flatnonzero(after & (trace.rate_kbps <= low_kbps))
    tail = trace.time_s >= trace.time_s[-1] - 10.0
    return {
        "converged_kbps": round(float(np.median(trace.rate_kbps[before])), 1),
        "backoff_s": round(float(trace.time_s[below[0]] - step_s), 3) if below.size else None,
        "settled_kbps": round(float(np.median(trace.rate_kbps[tail])), 1),
        "peak_delay_ms": round(float(trace.delay_s[after].max() * 1000.0), 1),
    }
