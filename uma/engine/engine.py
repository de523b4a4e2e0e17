"""The UMA engine's decisions as a state machine: events in, decisions out; no clock, no codec.

Units: times in seconds, rates in kbit/s, sizes in bits.

The SimPy world feeds it receiver reports, keyframe requests and the sender's frames, and carries
out what it returns (skip the frame, or transcode it at a rung, as an IDR or not). The engine keeps
what it needs to judge the downlink: the bandwidth estimate, the bits still in flight (sent
after the highest sequence number the receiver has reported), and when it last switched rung.

The tuning lives in `EngineConfig` so sweeps reach it: `stale_reports` (reports missing for this
many intervals mean the feedback path, and likely the downlink, is down), `max_backlog_ms` (frames
waiting in the network beyond this much sending time are not worth adding to), `presume_lost_ms`
(packets the receiver has not acknowledged after this long are presumed lost: a lost tail would
otherwise look outstanding forever and stall the engine) and `probe_interval_ms` (while
backlogged, still send a frame this often: a probe that keeps the reports coming).
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.config.scenario import EngineConfig, FeedbackConfig
from uma.engine.estimator import EstimatorState, initial_estimate, stale_decrease
from uma.engine.estimators import ESTIMATORS
from uma.engine.policy import POLICIES, PolicyView, highest_fitting
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = ["UmaEngine", "FrameDecision", "EngineEvent"]


@dataclass(frozen=True)
class FrameDecision:
    """What to do with one source frame.

    `scheduled` is False when the rung's frame rate leaves this frame out (no freeze: the rate is
    lower by design); `send` is False also when the engine skips a scheduled frame because the
    downlink is backlogged (the display will freeze).
    """

    frame: int
    rung: int
    scheduled: bool
    send: bool
    force_idr: bool
    reason: str = ""


@dataclass(frozen=True)
class EngineEvent:
    time_s: float
    kind: str
    detail: str


class UmaEngine:
    """Chooses, for each frame, whether and how to send it over the downlink."""

    def __init__(
        self,
        config: EngineConfig,
        *,
        rung_rates_kbps: tuple[float, ...],
        rung_fps: tuple[float, ...],
        source_fps: float,
        feedback: FeedbackConfig,
    ) -> None:
        self.config = config
        self.feedback = feedback
        self.rung_rates_kbps = rung_rates_kbps
        self.rung_fps = rung_fps
        self.source_fps = source_fps
        self.policy = POLICIES[config.policy]
        self.estimator: EstimatorState = initial_estimate(config.estimator)
        self.update_estimate = ESTIMATORS[config.estimator.kind]
        if config.policy == "fixed" and config.fixed_rung is not None:
            self.rung = min(config.fixed_rung, len(rung_rates_kbps) - 1)
        else:
            self.rung = highest_fitting(
                rung_rates_kbps, config.safety * self.estimator.estimate_kbps
            )
        self.last_switch_s = 0.0
        self.last_report_s = 0.0
        self.last_stale_decrease_s = 0.0
        self.last_idr_s = float("-inf")
        self.idr_pending = False
        self.cum_sent_bits: list[int] = [0]  # cum_sent_bits[seq + 1] = bits sent up to packet seq
        self.highest_seq = -1
        self.last_progress_s = 0.0
        self.last_sent_s = float("-inf")
        self.events: list[EngineEvent] = []

    # --- events in -------------------------------------------------------------------------
    def on_report(self, report: ReceiverReport, now_s: float) -> None:
        # A report cannot acknowledge more than was sent (a corrupt or forged report would
        # otherwise index past the sent packets).
        reported_seq = min(report.highest_seq, len(self.cum_sent_bits) - 2)
        if reported_seq > self.highest_seq:
            self.highest_seq = reported_seq
            self.last_progress_s = now_s
        self.last_report_s = now_s
        self.estimator = self.update_estimate(
            self.estimator,
            report,
            now_s=now_s,
            outstanding_bits=self.outstanding_bits,
            config=self.config.estimator,
        )

    def on_keyframe_request(self, request: KeyframeRequest, now_s: float) -> None:
        self.idr_pending = True
        self.events.append(EngineEvent(now_s, "keyframe_request", f"frame {request.frame}"))

    def on_packets_sent(self, sizes_bits: list[int]) -> int:
        """Record packets handed to the downlink; returns the first sequence number given them."""
        first_seq = len(self.cum_sent_bits) - 1
        total = self.cum_sent_bits[-1]
        for size in sizes_bits:
            total += size
            self.cum_sent_bits.append(total)
        return first_seq

    @property
    def outstanding_bits(self) -> int:
        """Bits sent after the highest sequence number the receiver has reported."""
        return self.cum_sent_bits[-1] - self.cum_sent_bits[self.highest_seq + 1]

    @property
    def estimate_kbps(self) -> float:
        return self.estimator.estimate_kbps

    # --- decisions out ---------------------------------------------------------------------
    def on_frame(
        self, frame: int, now_s: float, *, capacity_kbps: float | None = None
    ) -> FrameDecision:
        """Decide for source frame `frame`, arriving from the sender at `now_s`."""
        self._check_stale(now_s)
        if (
            self.outstanding_bits
            and now_s - self.last_progress_s > self.config.presume_lost_ms / 1000.0
        ):
            self.highest_seq = len(self.cum_sent_bits) - 2
            self.last_progress_s = now_s
        view = PolicyView(
            now_s=now_s,
            rung_rates_kbps=self.rung_rates_kbps,
            current_rung=self.rung,
            last_switch_s=self.last_switch_s,
            estimate_kbps=self.estimator.estimate_kbps,
            safety=self.config.safety,
            up_hold_s=self.config.up_hold_ms / 1000.0,
            capacity_kbps=capacity_kbps,
            fixed_rung=self.config.fixed_rung,
        )
        wanted = self.policy(view)
        switched = wanted != self.rung
        if switched:
            self.events.append(
                EngineEvent(
                    now_s,
                    "rung_switch",
                    f"{self.rung}->{wanted} estimate {self.estimator.estimate_kbps:.1f} kbps",
                )
            )
            self.rung = wanted
            self.last_switch_s = now_s

        if not self._scheduled(frame):
            return FrameDecision(
                frame, self.rung, scheduled=False, send=False, force_idr=False, reason="fps"
            )
        budget_bits = self.estimator.estimate_kbps * self.config.max_backlog_ms
        probe_due = now_s - self.last_sent_s >= self.config.probe_interval_ms / 1000.0
        if self.outstanding_bits > budget_bits and not switched and not probe_due:
            return FrameDecision(
                frame, self.rung, scheduled=True, send=False, force_idr=False, reason="backlog"
            )

        force_idr = switched
        min_gap_s = self.feedback.keyframe_min_interval_ms / 1000.0
        if self.idr_pending and now_s - self.last_idr_s >= min_gap_s:
            force_idr = True
        if force_idr:
            self.idr_pending = False
            self.last_idr_s = now_s
        self.last_sent_s = now_s
        return FrameDecision(frame, self.rung, scheduled=True, send=True, force_idr=force_idr)

    def _scheduled(self, frame: int) -> bool:
        # Keep frame i when the rung's frame clock ticks between i and i + 1 of the source's.
        ratio = min(1.0, self.rung_fps[self.rung] / self.source_fps)
        return int((frame + 1) * ratio + 1e-9) > int(frame * ratio + 1e-9)

    def _check_stale(self, now_s: float) -> None:
        interval_s = self.feedback.interval_ms / 1000.0
        if now_s - self.last_report_s <= self.config.stale_reports * interval_s:
            return
        if now_s - self.last_stale_decrease_s < interval_s:
            return
        self.estimator = stale_decrease(self.estimator, now_s=now_s, config=self.config.estimator)
        self.last_stale_decrease_s = now_s
