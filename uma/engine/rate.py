"""The engine's rate control: one object per `engine.estimator.kind`, a report in, a rate out.

Units: times in seconds (the controllers' own in ms), rates in kbit/s, sizes in bits.

Every kind has the same interface (`RateControl`): `on_report(report, now_s)` folds a receiver
report in and returns a probe to send (or None) and the events it caused; `on_silence(now_s)`
is asked at each frame decision while no report comes; `skip(frame_bits, queued_bits)` says
whether a frame should not be coded (Salsify's rule); `state` is the `EstimatorState` the rest
of the engine reads (the estimate the rate policy scales by `safety`, the queueing delay, the
received rate). `pads`: the kind wants padding behind each unit up to its estimate (a WebRTC
encoder sends at its target; uma's ladder sends at most a rung's rate).

- `uma`: `uma.control.UmaController` on the report's delivery (trains, queue, trend, loss),
  probes when application-limited, `on_silence` per report interval without a report, the
  technology's prior on a handover, the skip rule, and no frame coded while the controller is
  `paused` (no report for its `pause_ms`; never more than `max_skip_ms` in a row, unless
  still paused and the frame would not drain within that time at what arrived over the last
  second: `skip_limit_by_received`, a silent link told from a trickle);
  no refresh packet leaves while paused or while the reports are later than their own spacing
  allows (`ReportSpacing`, `refresh_held`: the refresh alone waits for the next report; a
  pause that early for the video cost a measured trace, docs/rate-control.md).
- `gcc`: `uma.control.GccController` (the published GCC), its probes, no skip.
- `webrtc`: aiortc's receiver-side estimator fed the report's packets (a REMB, as before the
  controllers: earlier results stay comparable), padding to its estimate, a decrease by
  `STALE_DECREASE` while reports are missing for `engine.stale_reports` intervals.

This module's `RATE_CONTROLS` is the only place the engine branches on the kind.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from uma.codecs import spec
from uma.config.scenario import EngineConfig, FeedbackConfig
from uma.control import (
    GccController,
    ProbeRequest,
    RateDecision,
    UmaController,
    UmaSettings,
    should_skip,
)
from uma.control.gcc_rate import GccRateSettings
from uma.engine.estimator import EstimatorState, windowed_received
from uma.engine.inflight import InFlight
from uma.engine.points import OperatingPoint
from uma.engine.records import EngineEvent
from uma.engine.reports import ReceiverReport

__all__ = [
    "RateControl",
    "ReportSpacing",
    "UmaRate",
    "GccRate",
    "WebrtcRate",
    "RATE_CONTROLS",
    "make_rate",
]

# The received rate the rest of the engine reads (the refresh's spend) is over this window.
RECEIVED_WINDOW_S = 1.0
# aiortc's estimate falls by this factor while reports are missing (as before the controllers).
STALE_DECREASE = 0.85


class RateControl:
    """The interface every kind implements (the base: no probes, no skips, no padding)."""

    pads = False

    def __init__(self, config: EngineConfig, feedback: FeedbackConfig) -> None:
        self.estimator = config.estimator
        self.oracle = config.policy == "oracle"  # it reads the capacity: never paused
        self.state = EstimatorState(estimate_kbps=config.estimator.initial_kbps)
        self.drained_queue = config.drained_queue  # nothing in flight: no queue ahead
        # With `engine.rung_floor`, the lowest skippable rung's rate (0: no floor): the least
        # rate the send gates judge a frame by (`gate_kbps`, uma's skip rule).
        self.floor_kbps = 0.0
        self.technology = ""  # the last the reports named
        self.handover = False  # the last report named a new technology (never the oracle)

    def on_report(
        self, report: ReceiverReport, now_s: float, inflight: InFlight | None = None
    ) -> tuple[ProbeRequest | None, list]:
        """Fold `report` in; `inflight` (None: not known), the sender's own knowledge of what
        the link owes: the oldest packet sent and not yet reported, the bits sent after the
        last packet reported."""
        raise NotImplementedError

    def on_silence(self, now_s: float) -> list:
        return []

    def skip(
        self, frame_bits: float, queued_bits: float, now_s: float, *, outstanding_bits: int = -1
    ) -> bool:
        return False

    def queue_ahead_ms(self, outstanding_bits: int) -> float:
        """The queueing delay a packet sent now is taken to meet (the pacer's deadline):
        the last report's; with `engine.drained_queue`, none once every packet sent has
        been reported (`outstanding_bits` 0: the packets that met that queue are out of it)."""
        if self.drained_queue and outstanding_bits == 0:
            return 0.0
        return self.state.queue_delay_ms

    def paused(self, now_s: float) -> bool:
        """Whether the sender should send nothing new it may hold back (the feedback has
        gone quiet)."""
        return False

    def gate_kbps(self, estimate_kbps: float, capacity_kbps: float | None = None) -> float:
        """The rate the backlog hold judges a frame by: the true `capacity_kbps` when given
        (the oracle's), else the estimate, at least `floor_kbps`."""
        if capacity_kbps is not None:
            return capacity_kbps
        return max(estimate_kbps, self.floor_kbps)

    def refresh_held(self, now_s: float) -> bool:
        """Whether the refresh should neither be ordered nor leave (`paused`, or the kind's
        own earlier sign that the feedback is late)."""
        return self.paused(now_s)

    def _named(self, technology: str) -> bool:
        """Note the technology a report names (none: unchanged); whether it differs from one
        named before (the first named is no handover). `handover` says the same for what
        follows the estimate: never for the oracle (it reads the capacity)."""
        changed = bool(technology and self.technology and technology != self.technology)
        self.technology = technology or self.technology
        self.handover = changed and not self.oracle
        return changed

    def skips_frame(
        self, point: OperatingPoint, queued_bits: int, now_s: float, outstanding_bits: int = -1
    ) -> bool:
        """Whether a frame at `point` is not coded (`skip` on its share of the point's rate;
        never a codec that may not be skipped for backlog). `outstanding_bits`: in flight
        after the last reported packet (-1: not known)."""
        if not spec(point.codec).skip_for_backlog or point.rate_kbps <= self.floor_kbps:
            return False
        frame_bits = point.rate_kbps * 1000.0 / point.fps
        return self.skip(frame_bits, queued_bits, now_s, outstanding_bits=outstanding_bits)

    def _follow(self, report: ReceiverReport, estimate_kbps: float, queue_ms: float | None):
        """`state` after `report` with `estimate_kbps` (the kind's own, already within
        [min_kbps, max_kbps]: each controller bounds its target) and its queueing delay."""
        window, received_kbps, loss = windowed_received(self.state, report, RECEIVED_WINDOW_S)
        self.state = replace(
            self.state,
            estimate_kbps=estimate_kbps,
            queue_delay_ms=self.state.queue_delay_ms if queue_ms is None else queue_ms,
            loss_fraction=loss,
            received_kbps=received_kbps,
            window=window,
        )


class ReportSpacing:
    """The spacing of the receiver's reports as they arrive here, smoothed as RFC 6298
    smooths a round trip (gain 1/8, the mean deviation 1/4): a report is late once the last
    came more than the smoothed spacing plus `deviations` mean deviations ago, at least
    `min_ms` and at most `max_ms` (the controller's pause)."""

    def __init__(self, *, deviations: float = 4.0, min_ms: float = 10.0, max_ms: float = 150.0):
        self.deviations, self.min_ms, self.max_ms = deviations, min_ms, max_ms
        self.last_s: float | None = None
        self.smoothed_ms: float | None = None
        self.deviation_ms = 0.0

    def on_report(self, now_s: float) -> None:
        if self.last_s is not None:
            spacing_ms = (now_s - self.last_s) * 1000.0
            if self.smoothed_ms is None:
                self.smoothed_ms, self.deviation_ms = spacing_ms, spacing_ms / 2.0
            else:
                error_ms = abs(spacing_ms - self.smoothed_ms)
                self.deviation_ms += (error_ms - self.deviation_ms) / 4.0
                self.smoothed_ms += (spacing_ms - self.smoothed_ms) / 8.0
        self.last_s = now_s

    @property
    def allowed_ms(self) -> float | None:
        """How long after a report the next one is late (None: no spacing seen yet)."""
        if self.smoothed_ms is None:
            return None
        allowed_ms = self.smoothed_ms + self.deviations * self.deviation_ms
        return min(max(allowed_ms, self.min_ms), self.max_ms)

    def late(self, now_s: float) -> bool:
        allowed_ms = self.allowed_ms
        if allowed_ms is None or self.last_s is None:
            return False
        return (now_s - self.last_s) * 1000.0 > allowed_ms


class UmaRate(RateControl):
    """uma's controller (`uma.control.UmaController`)."""

    def __init__(self, config: EngineConfig, feedback: FeedbackConfig) -> None:
        super().__init__(config, feedback)
        cfg = config.estimator
        self.controller = UmaController(
            UmaSettings(
                initial_kbps=cfg.initial_kbps,
                min_kbps=cfg.min_kbps,
                max_kbps=cfg.max_kbps,
                recover_after_silence=cfg.recover_after_silence,
                overdue_in_any_report=cfg.overdue_in_any_report,
                no_probe_while_owed=cfg.no_probe_while_owed,
                no_probe_into_silence=cfg.no_probe_into_silence,
                fixed_due_time=cfg.fixed_due_time,
                no_probe_while_paused=cfg.no_probe_while_paused,
                take_queued_drop=cfg.take_queued_drop,
                bounded_queued_drop=cfg.bounded_queued_drop,
                skip_limit_by_received=cfg.skip_limit_by_received,
                judge_silence=cfg.judge_silence,
                queue_from_owed=cfg.queue_from_owed,
            )
        )
        self._report_ms: float | None = None  # the last report's end, on the receiver's clock
        self._report_s = 0.0  # when it arrived here
        self._skipping_s: float | None = None  # since when frames are skipped in a row
        self.spacing = ReportSpacing()

    def on_report(
        self, report: ReceiverReport, now_s: float, inflight: InFlight | None = None
    ) -> tuple[ProbeRequest | None, list]:
        probe = None
        self.spacing.on_report(now_s)
        if report.delivery is not None:  # what arrived (over the old path, if it changed)
            due = None if inflight is None else inflight.oldest_outstanding()
            due_ms = None if due is None else (due[0] * 1000.0, due[1])
            owed_bits = None if inflight is None else inflight.outstanding_bits
            named = report.technology
            fresh = named if named and self.technology and named != self.technology else ""
            decision: RateDecision = self.controller.on_report(
                report.delivery, due=due_ms, owed_bits=owed_bits, technology=fresh
            )
            self._report_ms, self._report_s = report.delivery.end_ms, now_s
            self._follow(report, decision.target_kbps, self.controller.queue_ms)
            probe = decision.probe
        return probe, self._technology(report.technology, now_s)

    def _technology(self, technology: str, now_s: float) -> list:
        """A change of the technology the reports name: the controller's prior for it."""
        if not self._named(technology):
            return []
        decision = self.controller.on_handover(technology, now_s * 1000.0)
        self.state = replace(self.state, estimate_kbps=decision.target_kbps)
        detail = f"{technology} {decision.target_kbps:.1f} kbps ({decision.reason})"
        return [EngineEvent(now_s, "handover_prior", detail)]

    def on_silence(self, now_s: float) -> list:
        if self._report_ms is None:
            return []
        # The controller's clock is the receiver's: the time since the last report arrived.
        now_ms = self._report_ms + (now_s - self._report_s) * 1000.0
        decision = self.controller.on_silence(now_ms)
        if not decision.reason:
            return []
        self.state = replace(self.state, estimate_kbps=decision.target_kbps)
        return [EngineEvent(now_s, "silence", f"estimate {decision.target_kbps:.1f} kbps")]

    def paused(self, now_s: float) -> bool:
        """The controller's `paused` on its clock (the receiver's), from when the last report
        arrived here."""
        if self.oracle or self._report_ms is None:
            return False
        return self.controller.paused(self._report_ms + (now_s - self._report_s) * 1000.0)

    def refresh_held(self, now_s: float) -> bool:
        """`paused`, or no report for longer than the reports' own spacing allows
        (`ReportSpacing.late`): the refresh is the one stream that can wait for the next
        report, so its bits stay out of a handover's gap (never for the oracle)."""
        if self.oracle:
            return False
        return self.paused(now_s) or self.spacing.late(now_s)

    def skip(
        self, frame_bits: float, queued_bits: float, now_s: float, *, outstanding_bits: int = -1
    ) -> bool:
        """Salsify's rule on the controller's capacity and the queue it last saw (the pacer's
        bits plus the bottleneck's; with `engine.drained_queue` none at the bottleneck once
        `outstanding_bits` is 0), or no report for the controller's `pause_ms`; never for more
        than `max_skip_ms` in a row."""
        c, s = self.controller, self.controller.settings
        queue_ms = 0.0 if self.drained_queue and outstanding_bits == 0 else c.queue_ms
        ahead_bits = queued_bits + queue_ms * c.capacity_kbps
        skip = should_skip(frame_bits, ahead_bits, c.capacity_kbps, s.skip_budget_ms)
        skip = skip or self.paused(now_s)
        if skip:
            if self._skipping_s is None:
                self._skipping_s = now_s
            skip = now_s - self._skipping_s < s.max_skip_ms / 1000.0
            skip = skip or (s.skip_limit_by_received and self._silent(frame_bits, now_s))
        if not skip:
            self._skipping_s = None
        return skip

    def _silent(self, frame_bits: float, now_s: float) -> bool:
        """Paused, and the frame would not drain within the skip limit's length at what
        arrived over the last `RECEIVED_WINDOW_S`: the link is silent, not trickling."""
        budget_bits = self.state.received_kbps * self.controller.settings.max_skip_ms
        return self.paused(now_s) and frame_bits > budget_bits


class GccRate(RateControl):
    """The GCC baseline (`uma.control.GccController`): its target, its probes."""

    def __init__(self, config: EngineConfig, feedback: FeedbackConfig) -> None:
        super().__init__(config, feedback)
        cfg = config.estimator
        self.controller = GccController(
            GccRateSettings(
                initial_kbps=cfg.initial_kbps, min_kbps=cfg.min_kbps, max_kbps=cfg.max_kbps
            )
        )

    def on_report(
        self, report: ReceiverReport, now_s: float, inflight: InFlight | None = None
    ) -> tuple[ProbeRequest | None, list]:
        self._named(report.technology)
        if report.delivery is None:
            return None, []
        decision = self.controller.on_report(report.delivery)
        self._follow(report, decision.target_kbps, report.queue_delay_ms)
        return decision.probe, []


class WebrtcRate(RateControl):
    """aiortc's receiver-side estimator over the report's packets, carried as a REMB."""

    pads = True

    def __init__(self, config: EngineConfig, feedback: FeedbackConfig) -> None:
        super().__init__(config, feedback)
        from uma.engine.webrtc import RembEstimator

        self.remb = RembEstimator()
        self.interval_s = feedback.interval_ms / 1000.0
        self.stale_reports = config.stale_reports
        self._report_s = 0.0
        self._stale_s = 0.0

    def on_report(
        self, report: ReceiverReport, now_s: float, inflight: InFlight | None = None
    ) -> tuple[ProbeRequest | None, list]:
        self._named(report.technology)
        for record in () if report.delivery is None else report.delivery.records:
            self.remb.on_packet(
                arrival_s=record.arrival_ms / 1000.0, sent_s=record.send_ms / 1000.0,
                size_bits=record.size_bits,
            )  # fmt: skip
        estimate = self.remb.estimate_kbps
        if estimate is None:
            estimate = self.state.estimate_kbps
        else:  # aiortc's estimator knows no bounds: the REMB within the configured ones
            estimate = min(max(estimate, self.estimator.min_kbps), self.estimator.max_kbps)
        self._follow(report, estimate, report.queue_delay_ms)
        self._report_s = now_s
        return None, []

    def on_silence(self, now_s: float) -> list:
        """Reports missing for `stale_reports` intervals: one decrease per interval."""
        if now_s - self._report_s <= self.stale_reports * self.interval_s:
            return []
        if now_s - self._stale_s < self.interval_s:
            return []
        self._stale_s = now_s
        lowered = max(self.state.estimate_kbps * STALE_DECREASE, self.estimator.min_kbps)
        self.state = replace(self.state, estimate_kbps=lowered)
        return []


RATE_CONTROLS: dict[str, Callable[[EngineConfig, FeedbackConfig], RateControl]] = {
    "uma": UmaRate,
    "gcc": GccRate,
    "webrtc": WebrtcRate,
}


def make_rate(
    config: EngineConfig, feedback: FeedbackConfig, *, floor_kbps: float = 0.0
) -> RateControl:
    """The rate control `engine.estimator.kind` names; its send gates judge a frame by no less
    than `floor_kbps` (`engine.rung_floor`: the lowest skippable rung's rate)."""
    rate = RATE_CONTROLS[config.estimator.kind](config, feedback)
    rate.floor_kbps = floor_kbps
    return rate
