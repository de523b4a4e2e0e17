"""The engine's bandwidth estimator: delay- and loss-based, from receiver reports.

Units: rates in kbit/s, times in seconds, delays in milliseconds.

A bottleneck is over-used when its queue grows or it drops packets; then what got through is the
capacity, so the estimate falls to a fraction of the received rate (multiplicative decrease, at
most once per queue-drain time so one congestion episode is not punished many times). When the
queue is near empty the link may carry more, so the estimate grows by a fixed fraction per second
(like Google Congestion Control's increase), but never above twice the received rate, so an
application-limited stream cannot talk the estimate up without evidence. A report with nothing
received while data is outstanding means an outage: the estimate decays towards the floor.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from uma.config.scenario import EstimatorConfig
from uma.engine.reports import ReceiverReport

__all__ = ["EstimatorState", "initial_estimate", "update_estimate"]


@dataclass(frozen=True)
class EstimatorState:
    estimate_kbps: float
    last_decrease_s: float = float("-inf")
    queue_delay_ms: float = 0.0
    loss_fraction: float = 0.0


def initial_estimate(config: EstimatorConfig) -> EstimatorState:
    return EstimatorState(estimate_kbps=config.initial_kbps)


def update_estimate(
    state: EstimatorState,
    report: ReceiverReport,
    *,
    now_s: float,
    outstanding_bits: int,
    config: EstimatorConfig,
) -> EstimatorState:
    """Fold one receiver report into the estimate; a pure function."""
    received_kbps = report.received_kbps
    loss = report.loss_fraction
    queue_ms = report.queue_delay_ms
    estimate = state.estimate_kbps
    last_decrease_s = state.last_decrease_s

    if report.packets_received == 0:
        if outstanding_bits > 0:
            # Nothing arrives although data is in flight: an outage or a deep fade.
            estimate *= config.decrease_factor
        queue_ms = state.queue_delay_ms
    elif loss > config.loss_high or queue_ms > config.queue_high_ms:
        drain_s = max(report.interval_s, (queue_ms or 0.0) / 1000.0)
        if now_s - last_decrease_s >= drain_s:
            estimate = min(estimate, received_kbps) * config.decrease_factor
            last_decrease_s = now_s
    elif queue_ms < config.queue_low_ms:
        grown = estimate * (1.0 + config.increase_per_s * report.interval_s)
        estimate = min(grown, max(2.0 * received_kbps, estimate))

    estimate = min(max(estimate, config.min_kbps), config.max_kbps)
    return replace(
        state,
        estimate_kbps=estimate,
        last_decrease_s=last_decrease_s,
        queue_delay_ms=queue_ms if queue_ms is not None else 0.0,
        loss_fraction=loss,
    )
