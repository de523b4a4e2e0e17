"""Rate controllers in a pure closed loop over a measured trace: delay p95 and utilisation.

Units: ms, kbit/s (= bits per ms), bits. No SimPy, no codec. A sender sends, at each frame
instant (25 frames/s), one frame at its controller's current rate, capped at the ladder's top
(`app_max_kbps`: above it the stream is application-limited), cut into 1200-byte payloads with
40-byte headers all stamped with one send time, plus any padding probe the controller asked
for. A drop-tail FIFO (`queue_bytes`) serves them at the trace's capacity (integrated exactly
over the trace's steps, so an outage holds the queue), `delay_ms` each way. uma's sender skips a frame that would queue past
`UmaSettings.skip_budget_ms` behind the bits not yet reported (`uma.control.should_skip`), or
while its controller is `paused` (no report for `pause_ms`), as the engine's does. The
receiver feeds every arrival to the controller's feedback: `DeliveryTracker` reports for `uma` and `gcc`,
aiortc's `RembEstimator` for `webrtc`; the sender applies what comes back one `delay_ms` later.
`oracle` sends `headroom` x the true capacity with no feedback at all: a reference.

A frame's delay is from its send time to its last packet's arrival; a frame never delivered
whole (lost or skipped) counts as arriving with the next one that is (Salsify's video delay),
and as arriving at the run's end when none is. `utilisation` is
the bits delivered over the bits the link could carry while the stream could fill it
(the capacity capped at `app_max_kbps`), so an application-limited stream is not penalised.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["LoopSettings", "CONTROLLERS", "run_loop", "Link"]

CONTROLLERS = ("uma", "gcc", "webrtc", "oracle")
PAYLOAD_BITS = 1200 * 8
HEADER_BITS = 40 * 8


@dataclass(frozen=True)
class LoopSettings:
    duration_s: float = 300.0
    fps: float = 25.0
    delay_ms: float = 20.0
    queue_bytes: int = 300_000
    app_max_kbps: float = 1200.0
    initial_kbps: float = 300.0
    oracle_headroom: float = 0.85
    quiet_ms: float = 100.0  # how often the sender tells a silent controller the time
    uma: Any = None  # a `uma.control.UmaSettings` to try (None: its defaults)


class Link:
    """A trace's capacity as a cumulative-bits curve; when a packet entering at t leaves."""

    def __init__(self, times_s: np.ndarray, rates_kbps: np.ndarray, duration_s: float) -> None:
        self.start_ms = np.asarray(times_s, dtype=float) * 1000.0
        self.rates = np.asarray(rates_kbps, dtype=float)
        ends = np.append(self.start_ms[1:], duration_s * 1000.0)
        self.cumulative = np.concatenate([[0.0], np.cumsum(self.rates * (ends - self.start_ms))])
        self.end_ms = duration_s * 1000.0

    def bits_by(self, t_ms: float) -> float:
        i = int(np.searchsorted(self.start_ms, t_ms, side="right")) - 1
        i = min(max(i, 0), self.rates.size - 1)
        return float(self.cumulative[i] + self.rates[i] * (t_ms - self.start_ms[i]))

    def time_of(self, bits: float) -> float:
        """The first time the link has carried `bits` (inf past the trace's end)."""
        i = int(np.searchsorted(self.cumulative, bits, side="left")) - 1
        if i >= self.rates.size:
            return math.inf
        i = max(i, 0)
        while i < self.rates.size and self.rates[i] <= 0:
            i += 1
        if i >= self.rates.size:
            return math.inf
        return float(self.start_ms[i] + (bits - self.cumulative[i]) / self.rates[i])

    def capacity_at(self, t_ms: float) -> float:
        i = int(np.searchsorted(self.start_ms, t_ms, side="right")) - 1
        return float(self.rates[min(max(i, 0), self.rates.size - 1)])


class _Feedback:
    """The receiver's side and the controller, for one named controller."""

    def __init__(self, name: str, settings: LoopSettings) -> None:
        from uma.control import DeliveryTracker, GccController, UmaController, UmaSettings
        from uma.control.gcc_rate import GccRateSettings

        self.name = name
        self.delay_ms = settings.delay_ms  # the feedback's way back: the controller's clock
        self.tracker = DeliveryTracker()
        self.acked_bits = 0.0  # what the reports that reached the sender accounted for
        self.last_sent_ms = 0.0
        if name == "uma":
            uma = settings.uma or UmaSettings(initial_kbps=settings.initial_kbps)
            self.controller: Any = UmaController(uma)
        elif name == "gcc":
            rtt_ms = 2 * settings.delay_ms
            rate = GccRateSettings(initial_kbps=settings.initial_kbps)
            self.controller = GccController(rate, rtt_ms=rtt_ms)
        else:
            from uma.engine.webrtc import RembEstimator

            self.controller = RembEstimator()

    def on_arrival(self, seq: int, send_ms: float, arrival_ms: float, bits: int):
        """A decision (rate, probe) when this arrival produced feedback, else None."""
        if self.name == "webrtc":
            before = self.controller.updates
            self.controller.on_packet(
                arrival_s=arrival_ms / 1000.0, sent_s=send_ms / 1000.0, size_bits=bits
            )
            if self.controller.updates != before:
                return self.controller.estimate_kbps, None
            return None
        report = self.tracker.on_packet(seq, send_ms, arrival_ms, bits)
        if report is None:
            return None
        decision = self.controller.on_report(report)
        mean_bits = report.received_bits / max(report.packets, 1)
        self.acked_bits += report.received_bits + report.lost * mean_bits
        return decision.target_kbps, decision.probe

    def skips(self, frame_bits: float, sent_bits: float, now_ms: float) -> bool:
        """uma's skip rule: the frame would queue past the budget behind what is outstanding.

        Never for longer than `max_skip_ms` in a row: a frame then goes anyway, so a loss the
        reports have not seen yet cannot hold the sender silent for ever.
        """
        if self.name != "uma":
            return False
        from uma.control import should_skip

        outstanding = max(0.0, sent_bits - self.acked_bits)
        settings = self.controller.settings
        skip = should_skip(
            frame_bits, outstanding, self.controller.capacity_kbps, settings.skip_budget_ms
        ) or self.controller.paused(now_ms - self.delay_ms)
        if skip and now_ms - self.last_sent_ms < settings.max_skip_ms:
            return True
        self.last_sent_ms = now_ms
        return False

    def on_quiet(self, now_ms: float):
        if self.name == "uma":
            decision = self.controller.on_silence(now_ms)
            return decision.target_kbps, None
        return None

    def on_handover(self, technology: str, now_ms: float):
        if self.name == "uma":
            return self.controller.on_handover(technology, now_ms).target_kbps, None
        return None


def _packets(rate_kbps: float, fps: float) -> list[int]:
    frame_bits = rate_kbps / fps * 1000.0
    count = max(1, math.ceil(frame_bits / PAYLOAD_BITS))
    return [int(frame_bits / count) + HEADER_BITS] * count


class _Bottleneck:
    """The drop-tail FIFO: `send` returns a packet's arrival at the receiver, or None (dropped)."""

    def __init__(self, link: Link, settings: LoopSettings) -> None:
        self.link, self.settings = link, settings
        self.queue: deque[tuple[float, int]] = deque()  # (departure, bits)
        self.queued_bits = 0.0
        self.free_bits = 0.0  # the link's cumulative bits when it is next free

    def send(self, now_ms: float, bits: int) -> float | None:
        while self.queue and self.queue[0][0] <= now_ms:
            self.queued_bits -= self.queue.popleft()[1]
        if self.queued_bits + bits > self.settings.queue_bytes * 8:
            return None
        self.free_bits = max(self.free_bits, self.link.bits_by(now_ms)) + bits
        departure = self.link.time_of(self.free_bits)
        self.queue.append((departure, bits))
        self.queued_bits += bits
        return departure + self.settings.delay_ms


@dataclass
class _Run:
    """What one loop run accumulates."""

    frame_send: list = field(default_factory=list)
    frame_arrival: list = field(default_factory=list)
    pending: deque = field(default_factory=deque)  # (time the sender learns it, rate, probe)
    in_flight: deque = field(default_factory=deque)  # (arrival, seq, send, bits, frame)
    sent_bits: int = 0
    delivered_bits: int = 0
    last_feedback_ms: float = 0.0
    technology: str | None = None
    seq: int = 0


def _receive(run: _Run, feedback, now: float, s: LoopSettings, trace) -> None:
    """Arrivals up to one way before `now` reach the receiver; their feedback heads back."""
    while run.in_flight and run.in_flight[0][0] + s.delay_ms <= now:
        arrival, seq, send, bits, frame = run.in_flight.popleft()
        run.delivered_bits += bits
        if frame >= 0:
            run.frame_arrival[frame] = max(run.frame_arrival[frame], arrival)
        decision = feedback.on_arrival(seq, send, arrival, bits) if feedback else None
        if decision is not None:
            run.pending.append((arrival + s.delay_ms, *decision))
            run.last_feedback_ms = arrival + s.delay_ms
    if feedback is None:
        return
    if now - run.last_feedback_ms >= s.quiet_ms:
        quiet = feedback.on_quiet(now - s.delay_ms)
        if quiet is not None:
            run.pending.append((now, *quiet))
    labels = trace.technologies
    tech = labels[max(int(np.searchsorted(trace.times_s, now / 1000.0, "right")) - 1, 0)]
    if tech and run.technology is not None and tech != run.technology:
        change = feedback.on_handover(tech, now)
        if change is not None:
            run.pending.append((now, *change))
    run.technology = tech


def run_loop(
    trace, name: str, settings: LoopSettings | None = None, *, log: list | None = None
) -> dict[str, Any]:
    """One controller over the first `duration_s` of `trace` (a `uma.traces.Trace`).

    `log`, when given, gets one (time_ms, rate_kbps, queued_bits) per frame instant.
    """
    s = settings or LoopSettings()
    duration_s = min(s.duration_s, float(trace.duration_s))
    link = Link(trace.times_s, trace.rates_kbps, float(trace.duration_s))
    bottleneck = _Bottleneck(link, s)
    feedback = None if name == "oracle" else _Feedback(name, s)
    run = _Run()
    rate, probe = s.initial_kbps, None
    for index in range(int(duration_s * s.fps)):
        now = index * 1000.0 / s.fps
        _receive(run, feedback, now, s, trace)
        while run.pending and run.pending[0][0] <= now:
            _, rate, request = run.pending.popleft()
            probe = request or probe
        if name == "oracle":
            rate = s.oracle_headroom * link.capacity_at(now)
        sizes = _packets(min(rate, s.app_max_kbps), s.fps)
        if log is not None:
            log.append((now, rate, bottleneck.queued_bits))
        frame = len(run.frame_send)
        run.frame_send.append(now)
        run.frame_arrival.append(-math.inf)
        batch = [(size, frame) for size in sizes]
        if feedback is not None and feedback.skips(sum(sizes), run.sent_bits, now):
            batch = []
            run.frame_arrival[frame] = math.inf  # skipped: shown with the next frame that arrives
        if probe is not None:
            batch += [(probe.packet_bits, -1)] * probe.packets
            probe = None
        for size, owner in batch:
            run.sent_bits += size
            arrival = bottleneck.send(now, size)
            if arrival is None and owner >= 0:
                run.frame_arrival[owner] = math.inf  # a lost packet: the frame never completes
            elif arrival is not None:
                run.in_flight.append((arrival, run.seq, now, size, owner))
            run.seq += 1
    return _summary(name, run, link, duration_s, s)


def _summary(name: str, run: _Run, link: Link, duration_s: float, s: LoopSettings):
    sent_bits, delivered_bits = run.sent_bits, run.delivered_bits
    send = np.asarray(run.frame_send)
    arrival = np.asarray(run.frame_arrival, dtype=float)
    end_ms = duration_s * 1000.0
    arrival[~np.isfinite(arrival)] = np.inf  # lost, skipped, or not arrived within the run
    effective = np.minimum.accumulate(arrival[::-1])[::-1]
    delays = np.minimum(effective, end_ms) - send  # nothing after it arrived: until the end
    grid = np.arange(0.0, end_ms, 10.0)
    usable = sum(min(link.capacity_at(t), s.app_max_kbps) * 10.0 for t in grid)
    capacity = link.bits_by(end_ms)
    return {
        "controller": name,
        "delay_p95_ms": round(float(np.percentile(delays, 95)), 1) if delays.size else None,
        "delay_median_ms": round(float(np.median(delays)), 1) if delays.size else None,
        "utilisation": round(delivered_bits / usable, 4) if usable else None,
        "sent_over_capacity": round(sent_bits / capacity, 4) if capacity else None,
        "kbps_sent": round(sent_bits / end_ms, 1),
    }
