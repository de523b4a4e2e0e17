"""The UMA engine: events in, decisions out; no clock, no codec. It dispatches to its parts.

Units: times in seconds, rates in kbit/s, sizes in bits.

The world feeds it receiver reports, keyframe requests and the sender's frames, and carries out
what it returns (`uma.engine.decisions`). Outcomes come back as calls: `on_keyframe_sent` (a
keyframe request is settled only when an IDR really left), `on_init_done` (the model codec's
initialisation, after its modelled compute time), `on_coded` (the encoder re-initialised or
failed) and `on_unit_sent`. Its parts: the ladder (`uma.engine.ladder`), the bits in flight
(`uma.engine.inflight`), the model codec's sub-machine (`uma.engine.model`), the
description's delivery (`uma.engine.description`) and the padding rule (`uma.engine.probe`).

A failure of a region codec (no face found) moves to the lowest full-frame rung and leaves the
region rungs off the ladder for its section's `retry_ms`; a failure of the model codec moves to
the lowest rate rung (`uma.engine.model`). Tuning lives in `EngineConfig` so sweeps reach it.
"""

from __future__ import annotations

from uma.codecs import Role, model_names, names, spec
from uma.config.scenario import EngineConfig, FeedbackConfig
from uma.engine.decisions import EngineEvent, EngineOutcome, FrameDecision, UnitSent
from uma.engine.description import Delivery
from uma.engine.estimator import EstimatorState, initial_estimate, stale_decrease
from uma.engine.estimators import ESTIMATORS
from uma.engine.inflight import InFlight
from uma.engine.ladder import Ladder
from uma.engine.model import ModelMachine, Want
from uma.engine.points import OperatingPoint
from uma.engine.policy import (
    POLICIES,
    SWITCHING,
    PolicyView,
    SwitchView,
    highest_fitting,
    switch_settings,
)
from uma.engine.probe import padding_bits
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = ["UmaEngine", "FrameDecision", "EngineEvent"]


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
        description_bits: int = 0,
        description_chunks: int = 0,
        description_chunk_bits: int = 0,
    ) -> None:
        self.config, self.feedback, self.points = config, feedback, points
        self.ladder = Ladder(points, codec=config.codec, source_fps=source_fps)
        self.policy = POLICIES[config.policy]
        self.switch_policy = SWITCHING[config.switching.policy]
        model = self.ladder.model_codec or model_names()[0]
        self.model_config = getattr(config, spec(model).config_section)
        self.switch_settings = switch_settings(config, ladder=config.codec, model=model)
        self.coverage = coverage
        self.events: list[EngineEvent] = []
        self.counts: dict[str, int] = {}
        if self.ladder.model_point is None and not model_unavailable:
            model_unavailable = f"no {model} operating point on the ladder"
        self.model = ModelMachine(
            model,
            unavailable=model_unavailable,
            retry_s=config.switching.retry_ms / 1000.0,
            ladder_label=spec(config.codec).label,
            emit=self._emit,
            counts=self.counts,
        )
        for name in names(Role.REGION):
            self.counts[f"{spec(name).config_section}_failures"] = 0
        self.description = Delivery(
            bits=description_bits,
            chunks=description_chunks,
            chunk_bits=description_chunk_bits,
            share=self.model_config.description_share,
            codec=model,
            emit=self._emit,
        )
        self.inflight = InFlight()
        self.estimator: EstimatorState = initial_estimate(config.estimator)
        self.update_estimate = ESTIMATORS[config.estimator.kind]
        rate = self.ladder.rate
        if config.policy == "fixed" and config.fixed_rung is not None:
            self.rung = rate[min(config.fixed_rung, len(rate) - 1)]
        else:
            rates = tuple(points[i].rate_kbps for i in rate)
            self.rung = rate[highest_fitting(rates, config.safety * self.estimate_kbps)]
        self.switched_between = False  # the next frame sent starts a new stream
        self.codec_since_s = self.last_switch_s = self.last_stale_decrease_s = 0.0
        self.last_idr_s = self.last_sent_s = float("-inf")
        self.idr_pending = False

    def _emit(self, now_s: float, kind: str, detail: str) -> None:
        self.events.append(EngineEvent(now_s, kind, detail))

    # --- events in -------------------------------------------------------------------------
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

    def on_keyframe_request(self, request: KeyframeRequest, now_s: float) -> None:
        self.idr_pending = True
        self._emit(now_s, "keyframe_request", f"frame {request.frame}")

    def on_keyframe_sent(self, now_s: float) -> None:
        """An IDR (or intra parameter set) the engine asked for really left."""
        self.idr_pending = False
        self.last_idr_s = now_s

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
            self._switch_to(self.ladder.full_frame[0], now_s, "fallback")
            self.switched_between = True
        elif self.model.track_failed(reason, now_s):
            self._fall_back(self.ladder.allowed(now_s)[0], now_s)

    def on_packets_sent(self, sizes_bits: list[int]) -> int:
        """Packets handed to the downlink; returns the first sequence number given them."""
        return self.inflight.on_sent(sizes_bits)

    def on_unit_sent(self, sizes_bits: list[int], *, rung: int, frames: int = 1) -> UnitSent:
        """A coded unit of point `rung` (carrying `frames` frames) left as packets of
        `sizes_bits`: their first sequence number, and the padding to send behind it."""
        first_seq = self.inflight.on_sent(sizes_bits)
        pad = padding_bits(
            self.config,
            self.estimator,
            point=self.points[rung],
            model_config=self.model_config,
            interval_s=frames / min(self.points[rung].fps, self.ladder.source_fps),
            sent_bits=sum(sizes_bits),
        )
        return UnitSent(first_seq, pad)

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
        """Decide for source frame `frame`, arriving from the sender at `now_s`.

        `capacity_kbps` (the true capacity now) is for the oracle rate policy;
        `capacity_ahead_kbps` (the lowest true capacity over `switching.oracle_lookahead_ms`)
        for the oracle switching policy.
        """
        self._check_stale(now_s)
        self.inflight.presume_lost(now_s, self.config.presume_lost_ms / 1000.0)
        budget_kbps = self.config.safety * (
            capacity_kbps if self.config.policy == "oracle" else self.estimate_kbps
        )
        wanted, initialise = self._choose(now_s, capacity_kbps, budget_kbps, capacity_ahead_kbps)
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
        )  # fmt: skip
        if not self.ladder.scheduled(frame, self.rung):
            return _replace(decision, scheduled=False, reason="fps")
        probe_due = now_s - self.last_sent_s >= self.config.probe_interval_ms / 1000.0
        if self._backlogged(point, now_s, capacity_kbps) and not switched and not probe_due:
            return _replace(decision, reason="backlog")
        force_idr = switched
        self.switched_between = False
        min_gap_s = self.feedback.keyframe_min_interval_ms / 1000.0
        if self.idr_pending and now_s - self.last_idr_s >= min_gap_s:
            force_idr = True
        self.last_sent_s = now_s
        return _replace(decision, send=True, force_idr=force_idr)

    def _backlogged(self, point: OperatingPoint, now_s: float, capacity_kbps) -> bool:
        """Whether the downlink has more in flight than is worth adding to."""
        if not spec(point.codec).skip_for_backlog:
            # A model codec's few kbit/s are below any link the switch chooses it for: held
            # only while no report came for `outage_hold_ms` (in an outage they would arrive
            # tens of seconds late; a handover gap's are still in time).
            hold_s = getattr(self.config, spec(point.codec).config_section).outage_hold_ms
            return now_s - self.inflight.last_report_s > hold_s / 1000.0
        # The oracle judges by the true capacity: the estimate, unused, would call it too long.
        seen_kbps = self.estimate_kbps if capacity_kbps is None else capacity_kbps
        return self.outstanding_bits > seen_kbps * self.config.max_backlog_ms

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

    def _choose(self, now_s, capacity_kbps, budget_kbps, capacity_ahead_kbps):
        """The point to be on, and the model point to start initialising now (or None)."""
        view = PolicyView(
            now_s=now_s,
            points=self.points,
            current=self.rung,
            last_switch_s=self.last_switch_s,
            estimate_kbps=self.estimate_kbps,
            safety=self.config.safety,
            up_hold_s=self.config.up_hold_ms / 1000.0,
            capacity_kbps=capacity_kbps,
            fixed_rung=self.config.fixed_rung,
            ladder=self.ladder.allowed(now_s),
        )
        if self.config.switching.policy == "none":
            return self.policy(view), None
        ahead = None if capacity_ahead_kbps is None else self.config.safety * capacity_ahead_kbps
        family = self.switch_policy(
            SwitchView(
                now_s, self.ladder.family(self.rung), self.codec_since_s, budget_kbps,
                coverage=self.coverage, budget_ahead_kbps=ahead,
            ),
            self.switch_settings,
        )  # fmt: skip
        if family != self.model.name:
            self.description.stop_wait(now_s)
            self.model.leave(now_s)
            return self.policy(view), None
        want = self.model.want(now_s, description_ready=not self.description.pending)
        if want is Want.MODEL:
            return self.ladder.model_point, None
        if want is Want.LOWEST:
            return self.ladder.allowed(now_s)[0], None
        if want is Want.START:
            self.model.start(now_s, budget_kbps)
            return self.policy(view), self.ladder.model_point
        if want is Want.WAIT:  # wanted, but the receiver cannot render it yet: time counted
            self.description.wait(now_s)
        return self.policy(view), None

    def _check_stale(self, now_s: float) -> None:
        """Reports missing for `stale_reports` intervals: lower the estimate, once an interval."""
        interval_s = self.feedback.interval_ms / 1000.0
        if now_s - self.inflight.last_report_s <= self.config.stale_reports * interval_s:
            return
        if now_s - self.last_stale_decrease_s < interval_s:
            return
        self.estimator = stale_decrease(self.estimator, now_s=now_s, config=self.config.estimator)
        self.last_stale_decrease_s = now_s


def _region(codec: str) -> bool:
    return spec(codec).role is Role.REGION


def _replace(decision: FrameDecision, **changes) -> FrameDecision:
    from dataclasses import replace

    return replace(decision, **changes)
