"""The UMA engine's decisions as a state machine: events in, decisions out; no clock, no codec.

Units: times in seconds, rates in kbit/s, sizes in bits.

The SimPy world feeds it receiver reports, keyframe requests and the sender's frames, and carries
out what it returns (skip the frame, or code it at an operating point of the ladder, as an IDR
or not; start the model-based codec's initialisation). The outcomes of those actions come back
as events: `on_keyframe_sent` (a keyframe request is settled only when an IDR really left, so a
frame the engine could not decode never swallows one), `on_init_done` (the MBC initialisation
succeeded or failed, after its modelled compute time) and `on_track_failed`.

Switching (`engine.switching`): the switching policy names the codec to be on. A switch to MBC
first starts an initialisation on the engine's current decoded picture; frames keep flowing as
H.264 until it is done, then the engine moves to the MBC point. Without a content description
(`mbc_unavailable`), or after a failed initialisation, the engine stays on the lowest H.264 rung
while the policy wants MBC, and says why in its events (retrying after `retry_ms`).

Face-region rungs (`engine.face_region`, codec `h264-face`) are rungs of the rate ladder below
the full-frame ones: the rate policy climbs them like any rung. When the face-region encoder
finds no face (it reports a failure, as MBC's tracker does), the engine moves to the lowest
full-frame rung, leaves the face-region rungs off the ladder for `face_region.retry_ms` and
records why (`face_region_failed`). The engine keeps
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
from uma.engine.points import OperatingPoint, codec_indices, rate_indices
from uma.engine.policy import (
    POLICIES,
    SWITCHING,
    PolicyView,
    SwitchSettings,
    SwitchView,
    highest_fitting,
)
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = ["UmaEngine", "FrameDecision", "EngineEvent"]


@dataclass(frozen=True)
class FrameDecision:
    """What to do with one source frame.

    `rung` is the index of the operating point `point` in the engine's ladder (on an H.264-only
    ladder, the H.264 rung); `point` names the codec and the compute it models.
    `scheduled` is False when the point's frame rate leaves this frame out (no freeze: the rate
    is lower by design); `send` is False also when the engine skips a scheduled frame because
    the downlink is backlogged (the display will freeze). `init_mbc`: start the model-based
    codec's initialisation on this frame's decoded picture (then call `on_init_done`).
    """

    frame: int
    rung: int
    scheduled: bool
    send: bool
    force_idr: bool
    reason: str = ""
    point: OperatingPoint | None = None
    init_mbc: bool = False

    @property
    def codec(self) -> str:
        return self.point.codec if self.point is not None else "h264"


@dataclass(frozen=True)
class EngineEvent:
    time_s: float
    kind: str
    detail: str


def _family(codec: str) -> str:
    """The codec as switching policies see it: "mbc", or "h264" for the whole rate ladder."""
    return "mbc" if codec == "mbc" else "h264"


class UmaEngine:
    """Chooses, for each frame, whether and how to send it over the downlink."""

    def __init__(
        self,
        config: EngineConfig,
        *,
        points: tuple[OperatingPoint, ...],
        source_fps: float,
        feedback: FeedbackConfig,
        mbc_unavailable: str = "",
        coverage: tuple[tuple[float, str], ...] = (),
        description_bits: int = 0,
    ) -> None:
        self.config = config
        self.feedback = feedback
        self.points = points
        # The rate ladder (face-region and full-frame H.264, by rate) and its full-frame part.
        self.h264 = rate_indices(points)
        self.full_frame = codec_indices(points, config.codec) or self.h264
        self.face_blocked_until_s = float("-inf")
        mbc = codec_indices(points, "mbc")
        self.mbc_point = mbc[0] if mbc else None
        self.source_fps = source_fps
        self.policy = POLICIES[config.policy]
        self.switch_policy = SWITCHING[config.switching.policy]
        self.switch_settings = SwitchSettings(
            to_model_below_kbps=config.switching.to_mbc_below_kbps,
            to_ladder_above_kbps=config.switching.to_h264_above_kbps,
            min_dwell_s=config.switching.min_dwell_ms / 1000.0,
            lookahead_s=config.switching.lookahead_ms / 1000.0,
            low_technologies=tuple(config.switching.low_technologies),
        )
        self.coverage = coverage
        # The content description to deliver ahead of need (0 bits: nothing to deliver, or
        # the receiver is assumed to hold it). MBC is used only once a report confirms it.
        self.description_bits = description_bits
        self.description_acked_s: float | None = None if description_bits else 0.0
        self.description_wait_from_s: float | None = None
        self.description_wait_s = 0.0
        if self.mbc_point is None and not mbc_unavailable:
            mbc_unavailable = "no MBC operating point on the ladder"
        self.mbc_unavailable = mbc_unavailable
        self.estimator: EstimatorState = initial_estimate(config.estimator)
        self.update_estimate = ESTIMATORS[config.estimator.kind]
        rates = tuple(points[i].rate_kbps for i in self.h264)
        if config.policy == "fixed" and config.fixed_rung is not None:
            self.rung = self.h264[min(config.fixed_rung, len(self.h264) - 1)]
        else:
            self.rung = self.h264[
                highest_fitting(rates, config.safety * self.estimator.estimate_kbps)
            ]
        # Switching state: "off" (H.264), "initialising", "on" (sending MBC).
        self.mbc_state = "off"
        self.switched_between = False
        self.codec_since_s = 0.0
        self.mbc_blocked_until_s = float("-inf")
        self.mbc_blocked_reason = ""
        self.mbc_blocked_logged = False
        self.counts = {
            "inits": 0,
            "init_failures": 0,
            "track_failures": 0,
            "mbc_refused": 0,
            "face_region_failures": 0,
        }
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
        if report.description_complete and self.description_acked_s is None:
            self.description_acked_s = now_s
            self.events.append(
                EngineEvent(now_s, "description_delivered", f"{self.description_bits} bits")
            )
            if self.description_wait_from_s is not None:
                self.description_wait_s += now_s - self.description_wait_from_s
                self.description_wait_from_s = None
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

    def on_keyframe_sent(self, now_s: float) -> None:
        """An IDR (or intra parameter set) the engine asked for really left."""
        self.idr_pending = False
        self.last_idr_s = now_s

    def on_init_done(self, ok: bool, now_s: float, *, reason: str = "", evaluations: int = 0):
        """The MBC initialisation finished (after its modelled compute time)."""
        if self.mbc_state != "initialising":
            return
        if ok:
            self.mbc_state = "ready"
            self.events.append(
                EngineEvent(now_s, "mbc_init_done", f"{evaluations} evaluations; {reason}")
            )
            return
        self.counts["init_failures"] += 1
        self._block_mbc(now_s, f"initialisation failed: {reason}", "mbc_init_failed")

    def on_track_failed(self, reason: str, now_s: float) -> None:
        """Tracking lost the face and could not re-initialise: back to the lowest H.264 rung.

        On a face-region rung (no face found in the engine's picture): to the lowest
        full-frame rung, the face-region rungs off the ladder for `face_region.retry_ms`."""
        if self.points[self.rung].codec == "h264-face":
            self.counts["face_region_failures"] += 1
            self.face_blocked_until_s = now_s + self.config.face_region.retry_ms / 1000.0
            self.events.append(
                EngineEvent(now_s, "face_region_failed", f"{reason}; lowest full-frame rung")
            )
            self._switch_to(self.full_frame[0], now_s, "fallback")
            self.switched_between = True
            return
        if self.mbc_state != "on":
            return
        self.counts["track_failures"] += 1
        self._block_mbc(now_s, f"tracking failed: {reason}", "mbc_track_failed")

    def _block_mbc(self, now_s: float, reason: str, kind: str) -> None:
        self.mbc_state = "off"
        self.mbc_blocked_until_s = now_s + self.config.switching.retry_ms / 1000.0
        self.mbc_blocked_reason = reason
        self.mbc_blocked_logged = True
        self.events.append(EngineEvent(now_s, kind, reason))
        lowest = self._ladder(now_s)[0]
        if self.rung != lowest:
            self._switch_to(lowest, now_s, "fallback")
            self.switched_between = True  # the next frame sent starts the new stream

    @property
    def description_pending(self) -> bool:
        """The description still has to reach the receiver."""
        return self.description_acked_s is None

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
        self,
        frame: int,
        now_s: float,
        *,
        capacity_kbps: float | None = None,
        capacity_ahead_kbps: float | None = None,
    ) -> FrameDecision:
        """Decide for source frame `frame`, arriving from the sender at `now_s`.

        `capacity_kbps` (the true capacity now) is for the oracle rate policy;
        `capacity_ahead_kbps` (the lowest true capacity over `switching.oracle_lookahead_ms`)
        for the oracle switching policy.
        """
        self._check_stale(now_s)
        if (
            self.outstanding_bits
            and now_s - self.last_progress_s > self.config.presume_lost_ms / 1000.0
        ):
            self.highest_seq = len(self.cum_sent_bits) - 2
            self.last_progress_s = now_s
        view = PolicyView(
            now_s=now_s,
            points=self.points,
            current=self.rung,
            last_switch_s=self.last_switch_s,
            estimate_kbps=self.estimator.estimate_kbps,
            safety=self.config.safety,
            up_hold_s=self.config.up_hold_ms / 1000.0,
            capacity_kbps=capacity_kbps,
            fixed_rung=self.config.fixed_rung,
            ladder=self._ladder(now_s),
        )
        wanted, init_mbc = self._choose(view, now_s, capacity_kbps, capacity_ahead_kbps)
        switched = wanted != self.rung or self.switched_between
        if wanted != self.rung:
            self._switch_to(wanted, now_s, "rung_switch")

        point = self.points[self.rung]
        if not self._scheduled(frame):
            return self._hold(frame, point, init_mbc, scheduled=False, reason="fps")
        # The oracle judges the backlog by the true capacity too: its rates follow that, and
        # the estimate (which it does not use) would call its queue too long.
        seen_kbps = self.estimator.estimate_kbps if capacity_kbps is None else capacity_kbps
        budget_bits = seen_kbps * self.config.max_backlog_ms
        probe_due = now_s - self.last_sent_s >= self.config.probe_interval_ms / 1000.0
        # MBC frames are not skipped for backlog (the parameters' few kbit/s are below any
        # link the switch chooses MBC for), only while no report has come for
        # `mbc.outage_hold_ms`: in an outage they would fill the queue with parameters that
        # arrive tens of seconds late, while a handover gap's are still in time. The stream
        # starts again with an intra set (`uma.mbc.stream` restarts at a gap).
        if point.codec == "mbc":
            backlogged = now_s - self.last_report_s > self.config.mbc.outage_hold_ms / 1000.0
        else:
            backlogged = self.outstanding_bits > budget_bits
        if backlogged and not switched and not probe_due:
            return self._hold(frame, point, init_mbc, scheduled=True, reason="backlog")

        force_idr = switched
        self.switched_between = False
        min_gap_s = self.feedback.keyframe_min_interval_ms / 1000.0
        if self.idr_pending and now_s - self.last_idr_s >= min_gap_s:
            force_idr = True
        self.last_sent_s = now_s
        return FrameDecision(
            frame,
            self.rung,
            scheduled=True,
            send=True,
            force_idr=force_idr,
            point=point,
            init_mbc=init_mbc,
        )

    def _hold(
        self, frame: int, point: OperatingPoint, init_mbc: bool, *, scheduled: bool, reason: str
    ) -> FrameDecision:
        """A decision not to send `frame`, saying why."""
        return FrameDecision(
            frame,
            self.rung,
            scheduled=scheduled,
            send=False,
            force_idr=False,
            reason=reason,
            point=point,
            init_mbc=init_mbc,
        )

    def _switch_to(self, wanted: int, now_s: float, kind: str) -> None:
        old, new = self.points[self.rung], self.points[wanted]
        # A face-region rung is a rung of the rate ladder: moving between it and a full-frame
        # rung is a rung switch; a codec switch is between that ladder and MBC.
        if _family(old.codec) != _family(new.codec):
            self.codec_since_s = now_s
            self.events.append(
                EngineEvent(
                    now_s,
                    "codec_switch",
                    f"{old.codec}->{new.codec} estimate {self.estimator.estimate_kbps:.1f} kbps",
                )
            )
        else:
            self.events.append(
                EngineEvent(
                    now_s,
                    kind,
                    f"{self.rung}->{wanted} estimate {self.estimator.estimate_kbps:.1f} kbps",
                )
            )
        self.rung = wanted
        self.last_switch_s = now_s

    def _choose(
        self,
        view: PolicyView,
        now_s: float,
        capacity_kbps: float | None,
        capacity_ahead_kbps: float | None,
    ):
        """The point to be on, and whether to start an MBC initialisation now."""
        if self.config.switching.policy == "none":
            return self.policy(view), False
        on = _family(self.points[self.rung].codec)
        budget_kbps = self.config.safety * (
            capacity_kbps if self.config.policy == "oracle" else self.estimator.estimate_kbps
        )
        codec = self.switch_policy(
            SwitchView(
                now_s=now_s,
                codec=on,
                since_s=self.codec_since_s,
                budget_kbps=budget_kbps,
                coverage=self.coverage,
                budget_ahead_kbps=None
                if capacity_ahead_kbps is None
                else self.config.safety * capacity_ahead_kbps,
            ),
            self.switch_settings,
        )
        if codec == "h264":
            if self.description_wait_from_s is not None:
                self.description_wait_s += now_s - self.description_wait_from_s
                self.description_wait_from_s = None
            if self.mbc_state in ("initialising", "ready"):
                self.events.append(EngineEvent(now_s, "mbc_init_abandoned", "budget recovered"))
            self.mbc_state = "off"
            self.mbc_blocked_logged = False
            return self.policy(view), False
        if self.mbc_state == "on":
            return self.mbc_point, False
        if self.mbc_state == "ready":
            self.mbc_state = "on"
            return self.mbc_point, False
        if self.mbc_state == "initialising":
            return self.policy(view), False
        # Wanted, not yet started: refused (no description), waiting to retry, or begin now.
        reason = self.mbc_unavailable
        if not reason and now_s < self.mbc_blocked_until_s:
            reason = self.mbc_blocked_reason
        if not reason and self.description_acked_s is None:
            # Wanted, but the receiver cannot render MBC yet: H.264 meanwhile, time counted.
            if self.description_wait_from_s is None:
                self.description_wait_from_s = now_s
                self.events.append(
                    EngineEvent(now_s, "mbc_waiting_description", "description not delivered")
                )
            return self.policy(view), False
        if reason:
            if not self.mbc_blocked_logged:
                self.mbc_blocked_logged = True
                self.counts["mbc_refused"] += 1
                self.events.append(
                    EngineEvent(now_s, "mbc_refused", f"{reason}; lowest H.264 rung")
                )
            return self._ladder(now_s)[0], False
        self.mbc_state = "initialising"
        self.counts["inits"] += 1
        self.events.append(EngineEvent(now_s, "mbc_init_start", f"budget {budget_kbps:.1f} kbps"))
        return self.policy(view), True

    def _ladder(self, now_s: float) -> tuple[int, ...]:
        """The rate ladder now: without the face-region rungs while no face was found."""
        return self.full_frame if now_s < self.face_blocked_until_s else self.h264

    def _scheduled(self, frame: int) -> bool:
        # Keep frame i when the point's frame clock ticks between i and i + 1 of the source's.
        ratio = min(1.0, self.points[self.rung].fps / self.source_fps)
        return int((frame + 1) * ratio + 1e-9) > int(frame * ratio + 1e-9)

    def _check_stale(self, now_s: float) -> None:
        interval_s = self.feedback.interval_ms / 1000.0
        if now_s - self.last_report_s <= self.config.stale_reports * interval_s:
            return
        if now_s - self.last_stale_decrease_s < interval_s:
            return
        self.estimator = stale_decrease(self.estimator, now_s=now_s, config=self.config.estimator)
        self.last_stale_decrease_s = now_s
