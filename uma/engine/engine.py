"""The UMA engine: events in, actions out; no clock, no codec. It dispatches to its parts.

Units: times in seconds, rates in kbit/s, sizes in bits.

Each input is one call that returns what it causes (`uma.engine.decisions`). A source frame
takes at most three: `on_frame` (the decision: the point, whether intra, the initialisation to
start, the description's chunks, the refresh to code), `on_coded` (what coding it came to:
an intra picture left, the tracker re-initialised or failed, the refresh coded) and `on_sent`
(the coded unit, once its modelled compute time passed: its packets, the padding behind it and
the refresh's packets due). Between frames: `on_report`, `on_keyframe_request`, `on_init_done`
and `on_pace` (the pacer's packets due). The parts own their state and return actions; the
engine keeps the events and counts among them (`_keep`) and hands them on in `finish`.

Rate control is one object of `uma.engine.rate` (the kind `engine.estimator` names): each
report goes to it, and its estimate is what the rate policy reads; a probe it asks for leaves
at once as padding packets with one send stamp; at each frame decision it is told of silence
and asked whether to skip the frame; while it holds the refresh (`refresh_held`: paused, or
the reports late) no refresh packet leaves. A change of
rung within one codec and size retargets the open encoder (the decision's `target_kbps`, no
keyframe); a new codec or size is a new stream.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from uma.codecs import Role, spec
from uma.config.scenario import EngineConfig, FeedbackConfig
from uma.engine.decisions import (
    AdoptRefresh,
    CodedReport,
    EngineOutcome,
    FrameDecision,
    Initialise,
    OutgoingUnit,
    PaceDecision,
)
from uma.engine.pacing import held as pacing_held
from uma.engine.parts import DescriptionPlan, build_parts
from uma.engine.points import OperatingPoint, continues_stream
from uma.engine.records import EngineEvent, Tally
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = ["UmaEngine", "FrameDecision", "EngineEvent", "DescriptionPlan"]


class UmaEngine:
    """Chooses, for each frame, whether and how to send it over the downlink."""

    def __init__(
        self, config: EngineConfig, *, points: tuple[OperatingPoint, ...], source_fps: float,
        feedback: FeedbackConfig, model_unavailable: str = "",
        coverage: tuple[tuple[float, str], ...] = (), description: DescriptionPlan | None = None,
        payload_bytes: int = 1200,
    ) -> None:  # fmt: skip
        self.config, self.feedback, self.points = config, feedback, points
        self.oracle = config.policy == "oracle"
        parts = build_parts(
            config, points, source_fps=source_fps, model_unavailable=model_unavailable,
            coverage=coverage, description=description or DescriptionPlan(),
            feedback=feedback, payload_bytes=payload_bytes,
            keyframe_min_interval_s=feedback.keyframe_min_interval_ms / 1000.0,
        )  # fmt: skip
        self.ladder, self.model, self.description = parts.ladder, parts.model, parts.description
        self.refresh, self.outbox = parts.refresh, parts.outbox
        self.keyframes, self.position, self.sender = parts.keyframes, parts.position, parts.sender
        self.inflight, self.rate = parts.outbox.inflight, parts.rate
        self.events: list[EngineEvent] = []
        self.counts: dict[str, int] = {}
        self._keep(parts.declared)
        self.coder_rung = -1  # the point the world's coder is on (-1: none yet)
        self.last_sent_s = float("-inf")
        self.asked_idr = False  # the last frame sent was to be an IDR the engine asked for
        self.ordered = None  # the refresh ordered with the last frame sent

    def _keep(self, actions: list) -> list:
        """The one place the engine's events and counts are kept: from the actions returned."""
        for action in actions:
            if isinstance(action, EngineEvent):
                self.events.append(action)
            elif isinstance(action, Tally):
                self.counts[action.key] = self.counts.get(action.key, 0) + action.n
        return actions

    def on_report(self, report: ReceiverReport, now_s: float) -> list:
        self.inflight.on_report(report.highest_seq, now_s)
        actions = self.description.on_report(report.description_complete, now_s)
        probe, taken = self.rate.on_report(report, now_s, self.inflight)
        actions += taken + self.sender.probe(None if self.oracle else probe, now_s)
        if self.refresh is not None:
            actions += self.refresh.on_report(report, now_s, self.estimate_kbps, self.rate.handover)
        return self._keep(actions)

    def on_keyframe_request(self, request: KeyframeRequest, now_s: float) -> list:
        if request.refresh:  # a refresh lost: the next refresh is intra, no IDR
            return [] if self.refresh is None else self.refresh.request_intra(now_s)
        self.keyframes.request()
        return self._keep([EngineEvent(now_s, "keyframe_request", f"frame {request.frame}")])

    def on_init_done(self, ok: bool, now_s: float, *, reason: str = "", evaluations: int = 0):
        """The model codec's initialisation finished (after its modelled compute time)."""
        return self._keep(self._init_done(ok, now_s, reason, evaluations))

    def _init_done(self, ok: bool, now_s: float, reason: str, evaluations: int) -> list:
        actions = self.model.init_done(ok, now_s, reason=reason, evaluations=evaluations)
        if actions and not ok:
            lowest = self.ladder.allowed(now_s)[0]
            actions += self.position.fall_back(lowest, now_s, self.estimate_kbps)
        return actions

    def on_coded(self, report: CodedReport, now_s: float) -> list:
        """What coding a frame the engine decided to send came to (`CodedReport`)."""
        leftover = report.leftover
        actions = [] if leftover is None else self.sender.unit(leftover, now_s, self.estimator)
        self.coder_rung = report.rung
        if self.asked_idr and report.keyframe:
            self.keyframes.sent(now_s)
        if report.reinitialised:
            kind = f"{self.points[report.rung].codec}_reinit"
            actions.append(EngineEvent(now_s, kind, f"frame {report.frame}"))
        if report.failure:
            actions += self.position.coder_failed(report.failure, now_s, self.estimate_kbps)
        elif self.ordered is not None and self.refresh is not None:
            actions += self.refresh.on_coded(report.refresh, now_s)
        return self._keep(actions)

    def on_sent(self, unit: OutgoingUnit | None, now_s: float) -> list:
        """The frame's coded unit leaves (None: none), then the refresh's packets due."""
        actions = [] if unit is None else self.sender.unit(unit, now_s, self.estimator)
        return self._keep(actions + self.sender.refresh_due(now_s, self.rate))

    def on_pace(self, now_s: float, *, capacity_kbps: float | None = None) -> PaceDecision:
        """What the pacer lets out now; `capacity_kbps`: the true rate (the oracle's pace)."""
        oracle = self.oracle and capacity_kbps is not None
        decision, actions, needs_keyframe = self.sender.pace(
            now_s, seen_kbps=capacity_kbps if oracle else self.estimate_kbps, rung=self.rung,
            queue_delay_ms=self.rate.queue_ahead_ms(self.outstanding_bits),
        )  # fmt: skip
        self.keyframes.pending |= needs_keyframe
        self._keep(actions)
        return decision

    @property
    def rung(self) -> int:
        return self.position.rung

    @property
    def queued_bits(self) -> int:
        return self.outbox.queued_bits

    @property
    def outstanding_bits(self) -> int:
        return self.inflight.outstanding_bits

    @property
    def estimator(self):
        """What the rate control gives the rest of the engine (`EstimatorState`)."""
        return self.rate.state

    @property
    def estimate_kbps(self) -> float:
        return self.estimator.estimate_kbps

    def finish(self, end_s: float) -> EngineOutcome:
        """What the engine leaves behind when the run ends at `end_s`."""
        acked_s = self.description.acked_s if self.description.bits else None
        wait_s = self.description.wait_until(end_s)
        return EngineOutcome(tuple(self.events), dict(self.counts), acked_s, wait_s)

    def on_frame(
        self, frame: int, now_s: float, *, decoded: bool = True,
        capacity_kbps: float | None = None, lowest_kbps: Callable[[float, float], float] | None = None,
    ) -> FrameDecision:  # fmt: skip
        """Decide for source frame `frame`, arriving at `now_s` (`decoded`: the world has its
        picture). The oracle policies see the true capacity (`capacity_kbps`) and, switching,
        its lowest ahead (`lowest_kbps(start_s, end_s)`, a pure query of the trace)."""
        capacity_kbps = capacity_kbps if self.oracle else None
        silence = self.rate.on_silence(now_s)
        self.inflight.presume_lost(now_s, self.config.presume_lost_ms / 1000.0)
        budget_kbps = self.config.safety * (capacity_kbps if self.oracle else self.estimate_kbps)
        position = self.position
        wanted, initialise, chosen = position.choose(
            now_s, estimate_kbps=self.estimate_kbps, capacity_kbps=capacity_kbps,
            budget_kbps=budget_kbps, lowest_kbps=lowest_kbps, cut=bool(silence),
        )  # fmt: skip
        actions = silence + chosen
        switched = wanted != position.rung or position.switched_between
        if wanted != position.rung:
            actions += position.switch_to(wanted, now_s, "rung_switch", self.estimate_kbps)
        point = self.points[self.rung]
        decision = FrameDecision(
            frame, self.rung, scheduled=True, send=False, force_idr=False, point=point,
            initialise=initialise, estimate_kbps=self.estimate_kbps, queued_bits=self.queued_bits,
        )  # fmt: skip
        if initialise is not None and decoded:
            actions.append(Initialise(initialise, frame))
        sends = self.outbox.number(self.description.send(
            budget_kbps=budget_kbps, point_rate_kbps=point.rate_kbps, fps=self.ladder.source_fps,
            backlog_bits=self.estimate_kbps * self.config.max_backlog_ms / 2.0,
            outstanding_bits=self.outstanding_bits,
        ), now_s)  # fmt: skip
        decision = self._send_or_hold(decision, now_s, capacity_kbps, budget_kbps, switched)
        actions += decision.actions
        if initialise is not None and not decoded:
            actions += self._init_done(False, now_s, "no decoded picture to start from", 0)
        actions += sends
        adopted = self.refresh.take_adopted() if decision.send and self.refresh else None
        actions += [] if adopted is None else [AdoptRefresh(adopted)]
        if not decision.send or not decoded:
            actions += self.sender.refresh_due(now_s, self.rate)
        return replace(decision, actions=tuple(self._keep(actions)))

    def _send_or_hold(self, decision, now_s, capacity_kbps, budget_kbps, switched: bool):
        """Whether `decision`'s frame is sent: the point's frame rate, a backlog (unless a
        probe is due or a new stream starts); if so, intra or not and the refresh with it."""
        point = decision.point
        if not self.ladder.scheduled(decision.frame, self.rung):
            return replace(decision, scheduled=False, reason="fps")
        probe_due = now_s - self.last_sent_s >= self.config.probe_interval_ms / 1000.0
        seen_kbps = self.rate.gate_kbps(self.estimate_kbps, capacity_kbps)
        held = pacing_held(
            self.config, point, now_s, self.inflight, seen_kbps, queued_bits=self.queued_bits
        )
        if held and not switched and not probe_due:
            return replace(decision, reason="backlog")
        out_bits = self.outstanding_bits
        if not self.oracle and self.rate.skips_frame(point, self.queued_bits, now_s, out_bits):
            return replace(decision, reason="skip", actions=(Tally("skipped_frames", 1),))
        self.position.switched_between, self.last_sent_s = False, now_s
        self.ordered, actions = None, []
        if self.refresh is not None:
            received_kbps = float("inf") if self.oracle else self.estimator.received_kbps
            self.ordered, actions = self.refresh.on_frame(
                decision.frame, now_s, on_model=spec(point.codec).role is Role.MODEL,
                budget_kbps=budget_kbps, model_kbps=point.rate_kbps, received_kbps=received_kbps,
            )  # fmt: skip
        new_stream = not continues_stream(self.points, self.coder_rung, decision.rung)
        self.asked_idr = (switched and new_stream) or self.keyframes.due(now_s)
        keyframe = self.asked_idr or new_stream
        target_kbps = None if new_stream or self.rung == self.coder_rung else point.rate_kbps
        return replace(
            decision, send=True, force_idr=self.asked_idr, keyframe=keyframe,
            target_kbps=target_kbps, refresh=self.ordered, actions=tuple(actions),
        )  # fmt: skip
