"""The UMA engine: events in, decisions out; no clock, no codec. It dispatches to its parts.

Units: times in seconds, rates in kbit/s, sizes in bits.

The world feeds it receiver reports, keyframe requests and the sender's frames, and carries out
what it returns (`uma.engine.decisions`). Outcomes come back as calls: `on_keyframe_sent` (a
keyframe request is settled only when an IDR really left), `on_init_done` (the model codec's
initialisation, after its modelled compute time), `on_coded` (the encoder re-initialised or
failed) and `on_unit_sent`. Its parts: the ladder (`uma.engine.ladder`), the bits in flight
(`uma.engine.inflight`), the switching decision (`uma.engine.switching`) over the model
codec's sub-machine (`uma.engine.model`) and the description's delivery
(`uma.engine.description`), the backlog and padding rules (`uma.engine.pacing`), and when
configured the pacer with its own queue (`uma.engine.pacer`: the world queues units with
`on_unit_queued` and sends what `on_pace` lets out) and handover awareness
(`uma.engine.handover`: the estimate takes the reported technology's prior capacity).

A failure of a region codec (no face found) moves to the lowest full-frame rung and leaves the
region rungs off the ladder for its section's `retry_ms`; a failure of the model codec moves to
the lowest rate rung (`uma.engine.model`). Tuning lives in `EngineConfig` so sweeps reach it.
"""

from __future__ import annotations

from dataclasses import replace

from uma.codecs import Role, spec
from uma.config.scenario import EngineConfig, FeedbackConfig
from uma.engine import paced, refreshing
from uma.engine.decisions import (
    EngineEvent,
    EngineOutcome,
    FrameDecision,
    UnitSent,
)
from uma.engine.estimator import EstimatorState, initial_estimate, stale_decrease
from uma.engine.estimators import ESTIMATORS
from uma.engine.inflight import InFlight, Keyframes
from uma.engine.pacing import backlogged, frame_fits, padding_bits
from uma.engine.parts import DescriptionPlan, build_parts
from uma.engine.points import OperatingPoint
from uma.engine.policy import POLICIES, PolicyView
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = ["UmaEngine", "FrameDecision", "EngineEvent", "DescriptionPlan"]


class UmaEngine:
    """Chooses, for each frame, whether and how to send it over the downlink."""

    def __init__(
        self,
        config: EngineConfig,
        *,
        points: tuple[OperatingPoint, ...],
        source_fps: float,
        feedback: FeedbackConfig,
        model_unavailable: str = "",
        coverage: tuple[tuple[float, str], ...] = (),
        description: DescriptionPlan | None = None,
        technology_priors_kbps: dict[str, float] | None = None,
    ) -> None:
        self.config, self.feedback, self.points = config, feedback, points
        self.policy = POLICIES[config.policy]
        self.events: list[EngineEvent] = []
        parts = build_parts(
            config, points, source_fps=source_fps, model_unavailable=model_unavailable,
            coverage=coverage, description=description or DescriptionPlan(), emit=self._emit,
        )  # fmt: skip
        self.ladder, self.model, self.counts = parts.ladder, parts.model, parts.counts
        self.model_config, self.description = parts.model_config, parts.description
        self.switcher = parts.switcher
        self.inflight = InFlight()
        self.estimator: EstimatorState = initial_estimate(config.estimator)
        self.update_estimate = ESTIMATORS[config.estimator.kind]
        self.rung = self.ladder.initial(config, self.estimate_kbps)
        self.switched_between = False  # the next frame sent starts a new stream
        self.codec_since_s = self.last_switch_s = 0.0
        self.last_sent_s = float("-inf")
        self.keyframes = Keyframes(feedback.keyframe_min_interval_ms / 1000.0)
        self.pacer, self.handover = paced.build(config, technology_priors_kbps)
        self.next_unit = 0
        self.refresh = refreshing.build(self.model_config, emit=self._emit, counts=self.counts)

    def _emit(self, now_s: float, kind: str, detail: str) -> None:
        self.events.append(EngineEvent(now_s, kind, detail))

    def on_report(self, report: ReceiverReport, now_s: float) -> None:
        self.inflight.on_report(report.highest_seq, now_s)
        self.description.on_report(report.description_complete, now_s)
        self.estimator = self.update_estimate(
            self.estimator,
            report,
            now_s=now_s,
            outstanding_bits=self.outstanding_bits,
            config=self.config.estimator,
        )
        if self.handover is not None:
            paced.take_handover_prior(self, report.technology, now_s)
        refreshing.on_report(self, report)

    def on_keyframe_request(self, request: KeyframeRequest, now_s: float) -> None:
        if not refreshing.keyframe_request(self, request, now_s):
            self.keyframes.request()
            self._emit(now_s, "keyframe_request", f"frame {request.frame}")

    # The model-aided refresh (`uma.engine.refreshing`): its coded packets wait in the engine.
    on_refresh_coded = refreshing.on_refresh_coded
    on_refresh_pace = refreshing.on_refresh_pace

    def on_keyframe_sent(self, now_s: float) -> None:
        """An IDR (or intra parameter set) the engine asked for really left."""
        self.keyframes.sent(now_s)

    def on_init_done(self, ok: bool, now_s: float, *, reason: str = "", evaluations: int = 0):
        """The model codec's initialisation finished (after its modelled compute time)."""
        if self.model.init_done(ok, now_s, reason=reason, evaluations=evaluations):
            self._fall_back(self.ladder.allowed(now_s)[0], now_s)

    def on_coded(
        self, frame: int, now_s: float, *, rung: int, reinitialised: bool, failure: str
    ) -> None:
        """Point `rung`'s encoder coded `frame`: it re-initialised its tracker, or failed."""
        if reinitialised:
            self._emit(now_s, f"{self.points[rung].codec}_reinit", f"frame {frame}")
        if failure:
            self.on_track_failed(failure, now_s)

    def on_track_failed(self, reason: str, now_s: float) -> None:
        """The codec could not code the picture: a region codec found no face (to the lowest
        full-frame rung, region rungs blocked), or the model codec lost it."""
        codec = self.points[self.rung].codec
        if _region(codec):
            section = spec(codec).config_section
            self.counts[f"{section}_failures"] += 1
            retry_s = getattr(self.config, section).retry_ms / 1000.0
            self.ladder.block_regions(now_s + retry_s)
            self._emit(now_s, f"{section}_failed", f"{reason}; lowest full-frame rung")
            self._fall_back(self.ladder.full_frame[0], now_s)
        elif self.model.track_failed(reason, now_s):
            self._fall_back(self.ladder.allowed(now_s)[0], now_s)

    def on_packets_sent(self, sizes_bits: list[int]) -> int:
        """Packets handed to the downlink; returns the first sequence number given them."""
        return self.inflight.on_sent(sizes_bits)

    def on_unit_sent(self, sizes_bits: list[int], *, rung: int, frames: int = 1) -> UnitSent:
        """A coded unit of point `rung` (carrying `frames` frames) left as packets of
        `sizes_bits`: their first sequence number, and the padding to send behind it."""
        first_seq = self.inflight.on_sent(sizes_bits)
        interval_s = frames / min(self.points[rung].fps, self.ladder.source_fps)
        sent_bits = sum(sizes_bits) + refreshing.released_bits(self)
        pad = padding_bits(self, self.points[rung], interval_s, sent_bits=sent_bits)
        return UnitSent(first_seq, pad)

    # With the pacer on (`uma.engine.paced`): units and padding wait in the engine's queue,
    # and `on_pace` lets them out, numbered then.
    on_unit_queued = paced.unit_queued
    on_padding_queued = paced.padding_queued
    on_pace = paced.pace

    @property
    def queued_bits(self) -> int:
        """Bits waiting in the engine's own queue (0 without the pacer)."""
        return 0 if self.pacer is None else self.pacer.queued_bits

    @property
    def outstanding_bits(self) -> int:
        return self.inflight.outstanding_bits

    @property
    def estimate_kbps(self) -> float:
        return self.estimator.estimate_kbps

    def finish(self, end_s: float) -> EngineOutcome:
        """What the engine leaves behind when the run ends at `end_s`."""
        acked_s = self.description.acked_s if self.description.bits else None
        wait_s = self.description.wait_until(end_s)
        return EngineOutcome(tuple(self.events), dict(self.counts), acked_s, wait_s)

    # --- decisions out ---------------------------------------------------------------------
    def on_frame(
        self,
        frame: int,
        now_s: float,
        *,
        capacity_kbps: float | None = None,
        capacity_ahead_kbps: float | None = None,
    ) -> FrameDecision:
        """Decide for source frame `frame`, arriving from the sender at `now_s`. The oracle
        policies are given the true capacity now (`capacity_kbps`) and its lowest over
        `switching.oracle_lookahead_ms` ahead (`capacity_ahead_kbps`)."""
        _check_stale(self, now_s)
        self.inflight.presume_lost(now_s, self.config.presume_lost_ms / 1000.0)
        budget_kbps = self.config.safety * (
            capacity_kbps if self.config.policy == "oracle" else self.estimate_kbps
        )
        wanted, initialise = _choose(self, now_s, capacity_kbps, budget_kbps, capacity_ahead_kbps)
        switched = wanted != self.rung or self.switched_between
        if wanted != self.rung:
            self._switch_to(wanted, now_s, "rung_switch")
        point = self.points[self.rung]
        chunks = self.description.send(
            budget_kbps=budget_kbps,
            point_rate_kbps=point.rate_kbps,
            fps=self.ladder.source_fps,
            backlog_bits=self.estimate_kbps * self.config.max_backlog_ms / 2.0,
            inflight=self.inflight,
        )
        decision = FrameDecision(
            frame, self.rung, scheduled=True, send=False, force_idr=False, point=point,
            initialise=initialise, description=chunks, estimate_kbps=self.estimate_kbps,
            queued_bits=self.queued_bits,
        )  # fmt: skip
        if not self.ladder.scheduled(frame, self.rung):
            return replace(decision, scheduled=False, reason="fps")
        probe_due = now_s - self.last_sent_s >= self.config.probe_interval_ms / 1000.0
        seen_kbps = self.estimate_kbps if capacity_kbps is None else capacity_kbps
        held = _held(self, point, now_s, seen_kbps)
        if held and not switched and not probe_due:
            return replace(decision, reason="backlog")
        self.switched_between = False
        self.last_sent_s = now_s
        refresh = refreshing.decide(self, frame, now_s, point, budget_kbps)
        return replace(
            decision, send=True, force_idr=switched or self.keyframes.due(now_s), **refresh
        )

    def _switch_to(self, wanted: int, now_s: float, kind: str) -> None:
        old, new = self.points[self.rung], self.points[wanted]
        estimate = f"estimate {self.estimate_kbps:.1f} kbps"
        # Region and full-frame rungs are one rate ladder: moving between them is a rung
        # switch; a codec switch is between that ladder and the model codec.
        if self.ladder.family(self.rung) != self.ladder.family(wanted):
            self.codec_since_s = now_s
            self._emit(now_s, "codec_switch", f"{old.codec}->{new.codec} {estimate}")
        else:
            self._emit(now_s, kind, f"{self.rung}->{wanted} {estimate}")
        self.rung = wanted
        self.last_switch_s = now_s

    def _fall_back(self, lowest: int, now_s: float) -> None:
        if self.rung != lowest:
            self._switch_to(lowest, now_s, "fallback")
            self.switched_between = True  # the next frame sent starts the new stream


def _region(codec: str) -> bool:
    return spec(codec).role is Role.REGION


def _policy_view(engine: UmaEngine, now_s: float, capacity_kbps: float | None) -> PolicyView:
    """What the rate policy may look at now."""
    return PolicyView(
        now_s=now_s,
        points=engine.points,
        current=engine.rung,
        last_switch_s=engine.last_switch_s,
        estimate_kbps=engine.estimate_kbps,
        safety=engine.config.safety,
        up_hold_s=engine.config.up_hold_ms / 1000.0,
        capacity_kbps=capacity_kbps,
        fixed_rung=engine.config.fixed_rung,
        ladder=engine.ladder.allowed(now_s),
    )


def _choose(self: UmaEngine, now_s, capacity_kbps, budget_kbps, capacity_ahead_kbps):
    """The point to be on, and the model point to start initialising now (or None)."""
    view = _policy_view(self, now_s, capacity_kbps)
    if self.config.switching.policy == "none":
        return self.policy(view), None
    ahead = None if capacity_ahead_kbps is None else self.config.safety * capacity_ahead_kbps
    return self.switcher.choose(
        view,
        self.policy,
        since_s=self.codec_since_s,
        budget_kbps=budget_kbps,
        budget_ahead_kbps=ahead,
    )


def _check_stale(self: UmaEngine, now_s: float) -> None:
    """Reports missing for `stale_reports` intervals: lower the estimate, once an interval."""
    interval_s = self.feedback.interval_ms / 1000.0
    if self.inflight.stale_due(now_s, interval_s, self.config.stale_reports):
        self.estimator = stale_decrease(self.estimator, now_s=now_s, config=self.config.estimator)


def _held(self: UmaEngine, point, now_s: float, seen_kbps: float) -> bool:
    """Hold this frame: too much in flight, or (frame sizing on) it would not drain in time."""
    held = backlogged(
        self.config, point, now_s, self.inflight, seen_kbps, queued_bits=self.queued_bits
    )
    fit = self.config.pacer.fit_frames
    if fit > 0 and self.pacer is not None and not held:
        held = not frame_fits(
            point, queued_bits=self.queued_bits, slack_frames=fit,
            rate_kbps=seen_kbps * self.config.pacer.rate_factor,
            fps=min(point.fps, self.ladder.source_fps),
        )  # fmt: skip
    return held
