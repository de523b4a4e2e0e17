"""The engine's bandwidth estimator: delay- and loss-based, from receiver reports.

Units: rates in kbit/s, times in seconds, delays in milliseconds.

Reports arrive every ~100 ms, too few packets each to measure a slow link, so the received rate
and loss are taken over a sliding window of recent reports (`window_s`). A bottleneck is
over-used when its queue grows (or it loses many packets): the link was busy, so what got
through over the window is the capacity, and the estimate falls to a fraction of it
(multiplicative decrease, at most once per queue-drain time, so one congestion episode is not
punished many times; but once per window when the received rate is below `collapse_below` of
the estimate, so a collapse of the link is followed within seconds). When the queue is near empty the link may carry more, so the estimate grows
by a fixed fraction per second (like Google Congestion Control's increase), but not above three
times the received rate, so an application-limited stream cannot talk the estimate up without
evidence. Reports with nothing received while data is in flight mean an outage: the estimate
decays towards the floor.

With `trend_window_s` above 0 it also reads the trend of the queueing delay the reports carry
(as WebRTC's trendline estimator reads the one-way delay gradient): the least-squares slope of
the reports' queueing delays over that window. A queue growing faster than
`trend_high_ms_per_s` is over-use before it stands (a decrease, once per window, even below
`queue_high_ms`); the estimate grows only while the delay is not rising, and never above
`increase_cap` x the received rate (it can grow no faster than it can measure).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from uma.config.scenario import EstimatorConfig
from uma.engine.reports import ReceiverReport

__all__ = [
    "EstimatorState",
    "initial_estimate",
    "update_estimate",
    "stale_decrease",
    "windowed_received",
    "delay_trend_ms_per_s",
]


@dataclass(frozen=True)
class EstimatorState:
    estimate_kbps: float
    last_decrease_s: float = float("-inf")
    queue_delay_ms: float = 0.0
    loss_fraction: float = 0.0
    received_kbps: float = 0.0
    # (interval_s, received_bits, packets_received, packets_lost) of recent reports, newest last
    window: tuple[tuple[float, int, int, int], ...] = ()
    # (sent_s, queue_delay_ms) of recent reports that received something, newest last
    delays: tuple[tuple[float, float], ...] = ()
    trend_ms_per_s: float = 0.0


def initial_estimate(config: EstimatorConfig) -> EstimatorState:
    return EstimatorState(estimate_kbps=config.initial_kbps)


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


def delay_trend_ms_per_s(delays: tuple[tuple[float, float], ...]) -> float:
    """The least-squares slope of (time_s, delay_ms) samples; 0 with fewer than three."""
    if len(delays) < 3:
        return 0.0
    times = [t for t, _ in delays]
    values = [d for _, d in delays]
    mean_t, mean_d = sum(times) / len(times), sum(values) / len(values)
    spread = sum((t - mean_t) ** 2 for t in times)
    if spread <= 0.0:
        return 0.0
    return sum((t - mean_t) * (d - mean_d) for t, d in delays) / spread


def _bounded(estimate_kbps: float, config: EstimatorConfig) -> float:
    return min(max(estimate_kbps, config.min_kbps), config.max_kbps)


def stale_decrease(
    state: EstimatorState, *, now_s: float, config: EstimatorConfig
) -> EstimatorState:
    """One multiplicative decrease when reports stop coming (the feedback path is silent).

    Only the estimate and the time of the decrease change: the report window and the received
    rate are kept, so the first report after the silence is judged against what came before.
    """
    return replace(
        state,
        estimate_kbps=_bounded(state.estimate_kbps * config.decrease_factor, config),
        last_decrease_s=now_s,
    )


def update_estimate(
    state: EstimatorState,
    report: ReceiverReport,
    *,
    now_s: float,
    outstanding_bits: int,
    config: EstimatorConfig,
) -> EstimatorState:
    """Fold one receiver report into the estimate; a pure function."""
    window, received_kbps, loss = windowed_received(state, report, config.window_s)
    queue_ms = report.queue_delay_ms
    estimate = state.estimate_kbps
    last_decrease_s = state.last_decrease_s

    delays, trend = state.delays, state.trend_ms_per_s
    if config.trend_window_s > 0 and report.queue_delay_ms is not None:
        delays = tuple(
            item for item in delays if item[0] > report.sent_s - config.trend_window_s
        ) + ((report.sent_s, report.queue_delay_ms),)
        trend = delay_trend_ms_per_s(delays)
    rising = config.trend_window_s > 0 and trend > config.trend_high_ms_per_s

    if report.packets_received == 0:
        if outstanding_bits > 0:
            # Nothing arrives although data is in flight: an outage or a deep fade.
            estimate *= config.decrease_factor ** (report.interval_s / config.window_s)
        queue_ms = state.queue_delay_ms
    elif rising and queue_ms <= config.queue_high_ms and loss <= config.loss_high:
        # The queue is building: back off now, before it stands.
        if now_s - last_decrease_s >= config.window_s:
            estimate = min(estimate, received_kbps) * config.decrease_factor
            last_decrease_s = now_s
    elif loss > config.loss_high or queue_ms > config.queue_high_ms:
        drain_s = max(config.window_s, queue_ms / 1000.0)
        if received_kbps < config.collapse_below * estimate:
            # The link collapsed (a handover to a slower technology): what a fresh window
            # received is the capacity; waiting for the queue to drain would keep sending at
            # the old rate into it for seconds.
            drain_s = config.window_s
        if now_s - last_decrease_s >= drain_s:
            estimate = min(estimate, received_kbps) * config.decrease_factor
            last_decrease_s = now_s
    elif queue_ms < config.queue_low_ms and not (config.trend_window_s > 0 and trend > 0):
        grown = estimate * (1.0 + config.increase_per_s * report.interval_s)
        estimate = min(grown, max(config.increase_cap * received_kbps, estimate))

    estimate = _bounded(estimate, config)
    return replace(
        state,
        estimate_kbps=estimate,
        last_decrease_s=last_decrease_s,
        queue_delay_ms=queue_ms,
        loss_fraction=loss,
        received_kbps=received_kbps,
        window=window,
        delays=delays,
        trend_ms_per_s=trend,
    )
