"""What the engine's rate control gives the rest of the engine, and the received rate over a window.

Units: rates in kbit/s, times in seconds, delays in milliseconds.

`EstimatorState` is the rate control's view (`uma.engine.rate`): the estimate the rate policy
scales by `safety`, the queueing delay the pacer and the refresh read, the received rate and
loss over the recent reports (`windowed_received`).
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.engine.reports import ReceiverReport

__all__ = ["EstimatorState", "windowed_received"]


@dataclass(frozen=True)
class EstimatorState:
    estimate_kbps: float
    queue_delay_ms: float = 0.0
    loss_fraction: float = 0.0
    received_kbps: float = 0.0
    # (interval_s, received_bits, packets_received, packets_lost) of recent reports, newest last
    window: tuple[tuple[float, int, int, int], ...] = ()


def windowed_received(state: EstimatorState, report: ReceiverReport, window_s: float):
    """(window, received_kbps, loss_fraction) over the recent reports, `report` included."""
    window = state.window + (
        (report.interval_s, report.received_bits, report.packets_received, report.packets_lost),
    )
    total_s = sum(item[0] for item in window)
    while len(window) > 1 and total_s - window[0][0] >= window_s:
        total_s -= window[0][0]
        window = window[1:]
    bits = sum(item[1] for item in window)
    received = sum(item[2] for item in window)
    lost = sum(item[3] for item in window)
    rate_kbps = bits / total_s / 1000.0 if total_s > 0 else 0.0
    loss = lost / (received + lost) if received + lost else 0.0
    return window, rate_kbps, loss
