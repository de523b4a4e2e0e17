"""The engine's sections: rate policy, full-frame codec and ladder, estimator, switching.

Units live in key names (`_kbps`, `_ms`). The names `engine.policy`, `engine.estimator.kind`
and `engine.switching.policy` may take are the `Literal`s here; the tuples of names derive
from them, and `Scenario.model_validate` checks them as loading a file does.
"""

from __future__ import annotations

from typing import Annotated, Literal, get_args

from pydantic import AllowInfNan, Field, Strict, ValidationInfo, field_validator, model_validator

from uma.codecs import full_frame_names
from uma.config.codecs import FaceRegionConfig, MbcConfig
from uma.config.technologies import check_technologies
from uma.config.types import Bool, NonNeg, NonNegInt, PosInt, PosNum, Section, Str

__all__ = [
    "EngineConfig",
    "EstimatorConfig",
    "SwitchingConfig",
    "PacerConfig",
    "POLICY_NAMES",
    "ESTIMATOR_KINDS",
    "SWITCHING_NAMES",
    "CLIMB_NAMES",
    "PolicyName",
    "EstimatorKind",
    "SwitchingName",
]


# The rate policies `engine.policy` may name; `uma.engine.policy.POLICIES` implements each.
PolicyName = Literal["throughput", "oracle", "fixed"]
POLICY_NAMES: tuple[str, ...] = get_args(PolicyName)
# Rate control the engine can follow (`uma.engine.rate.RATE_CONTROLS`): uma's controller, the
# GCC baseline, or WebRTC's receiver-side estimator (aiortc's port) carried back as a REMB.
EstimatorKind = Literal["uma", "gcc", "webrtc"]
ESTIMATOR_KINDS: tuple[str, ...] = get_args(EstimatorKind)
# Switching policies `engine.switching.policy` may name (`uma.engine.policy.SWITCHING`).
SwitchingName = Literal["none", "threshold", "predictive", "oracle"]
SWITCHING_NAMES: tuple[str, ...] = get_args(SwitchingName)
# How the throughput policy climbs after `up_hold_ms` (`uma.engine.policy.CLIMBS`): one rung
# (`step`), a stream's highest fitting rung at once (`stream`, the default since session 24),
# the highest fitting rung, of a new size only with the margin (`fit`); docs/rate-control.md,
# branch rc23.
ClimbName = Literal["step", "stream", "fit"]
CLIMB_NAMES: tuple[str, ...] = get_args(ClimbName)


class EstimatorConfig(Section):
    """The engine's rate control (`uma.engine.rate`): which kind, and the bounds of its rate.

    `uma`: uma's controller (`uma.control.UmaController`, the default); `gcc`: the GCC
    baseline written from the published description (`uma.control.GccController`); `webrtc`:
    aiortc's port of webrtc.org's receiver-side estimator carried back as a REMB. The old
    estimator's tuning keys are retired (`uma.config.retired`).

    `recover_after_silence` (`uma` only; off, today's behaviour): after a silence cut, the
    first report with packets asks for a probe sized for the estimate before the cut and its
    measurement is taken whole (`uma.control.UmaSettings`; docs/rate-control.md, `rc11`).
    `overdue_in_any_report` (`uma` only; off): a report with packets, not only an empty one,
    starts the quiet clock at the due time of the packet after them when that one is overdue
    (and pauses the sender at once; docs/rate-control.md, `rc13`). `no_probe_while_owed`
    (`uma` only; off): no probe after a report that counted a packet due before its end.
    `no_probe_into_silence` (`uma` only; off): no probe once the quiet clock has run a
    silence's length (the cut is due first).
    `fixed_due_time` (`uma` only; on): an outstanding packet's time at the estimate is
    taken when it is first found due, so a silence cut does not move its due time later.
    `no_probe_while_paused` (`uma` only; on): no probe while the sender is paused.
    `take_queued_drop` (`uma` only; off): a train that measures less than the estimate while
    the report's queue builds past the controller's target is taken whole.
    `bounded_queued_drop` (`uma` only; off): such a train is taken whole once the queue
    builds past the controller's low mark, but one report at most halves the estimate.
    `skip_limit_by_received` (`uma` only; on): past the skip rule's 1-s limit a frame is
    still skipped while the sender is paused and the frame would not drain within that limit
    at what arrived over the last second (a silent link, not a trickle).
    `judge_silence` (`uma` only; off): a silence's cut is also undone when, on the same path
    and soon after, the packets it held up drain as a train at the estimate before the cut
    (`uma.control.silence`; docs/rate-control.md, `rc22`).
    `queue_from_owed` (`uma` only; on): the queue the controller drains is at most what the
    sender still has in flight after the report, at the estimate (a backlog an outage left
    behind a paused sender is gone, not a standing queue; docs/measured.md, section 19).
    """

    initial_kbps: PosNum = 300.0
    min_kbps: PosNum = 5.0
    max_kbps: PosNum = 20000.0
    # Which kind: `engine.estimator: gcc` is short for `engine.estimator: {kind: gcc}`.
    kind: EstimatorKind = "uma"
    recover_after_silence: Bool = False
    overdue_in_any_report: Bool = False
    no_probe_while_owed: Bool = False
    no_probe_into_silence: Bool = False
    fixed_due_time: Bool = True
    no_probe_while_paused: Bool = True
    take_queued_drop: Bool = False
    bounded_queued_drop: Bool = False
    skip_limit_by_received: Bool = True
    judge_silence: Bool = False
    queue_from_owed: Bool = True

    @model_validator(mode="after")
    def _consistent(self) -> EstimatorConfig:
        if self.min_kbps > self.max_kbps:
            raise ValueError(
                f"min_kbps ({self.min_kbps:g}) must not exceed max_kbps ({self.max_kbps:g})"
            )
        if not self.min_kbps <= self.initial_kbps <= self.max_kbps:
            raise ValueError(
                f"initial_kbps ({self.initial_kbps:g}) must lie within min_kbps "
                f"({self.min_kbps:g}) and max_kbps ({self.max_kbps:g})"
            )
        return self

    @model_validator(mode="before")
    @classmethod
    def _kind_shorthand(cls, data):
        if isinstance(data, str):
            if data not in ESTIMATOR_KINDS:
                raise ValueError(f"expected one of {', '.join(ESTIMATOR_KINDS)}")
            return {"kind": data}
        return data


class PacerConfig(Section):
    """The engine's pacer and its queue (`uma.engine.pacer`); off: units go straight to the
    downlink.

    Packets leave at `rate_factor` x the estimate (the oracle's true capacity; libwebrtc's
    pacing factor, 2.5, so a frame's packets leave as a train that measures the link, not the
    pacer), with `burst_ms` of that rate as the burst allowance; a frame that would leave
    later than its capture time + `deadline_ms` (less the reported queueing delay) is dropped
    in the engine, and a keyframe follows; padding waits at most `padding_wait_ms`.
    """

    enabled: Bool = True
    rate_factor: PosNum = 2.5
    burst_ms: PosNum = 40.0
    deadline_ms: PosNum = 1000.0
    padding_wait_ms: NonNeg = 100.0


class SwitchingConfig(Section):
    """When to switch between H.264 and the model-based codec (`uma.engine.policy`).

    `none`: H.264 only. `threshold`: to MBC when safety x estimate falls below
    `to_mbc_below_kbps`, back when it rises above `to_h264_above_kbps` (the gap is the
    hysteresis), never sooner than `min_dwell_ms` after the last codec change; after a failed
    initialisation the engine stays on the lowest H.264 rung and tries again `retry_ms` later.
    `predictive`: the thresholds, plus the route's technology segments as a coverage map: to
    MBC `lookahead_ms` before a segment of `low_technologies` begins, and not back while one
    is that near or under way. `oracle`: knows the trace (an upper bound): on MBC while the
    true capacity anywhere in the next `oracle_lookahead_ms` is below `to_mbc_below_kbps`,
    back once all of that window is above `to_h264_above_kbps`; it scales the capacity by
    `safety`. Its window need only cover an initialisation (about 0.1 s modelled, `engine.mbc`)
    and the first parameter packet (4 frames, 0.16 s): 1 s by default.
    `calm_ms` (`threshold` and `predictive`; 0, off, today's behaviour): no switch from MBC
    back to H.264 until `calm_ms` have passed since the estimate was last cut for a silence
    (an on/off link's off-periods; docs/rate-control.md, branch rc25).
    """

    policy: SwitchingName = "none"
    to_mbc_below_kbps: PosNum = 30.0
    to_h264_above_kbps: PosNum = 60.0
    min_dwell_ms: NonNeg = 3000.0
    retry_ms: PosNum = 5000.0
    lookahead_ms: NonNeg = 3000.0
    oracle_lookahead_ms: NonNeg = 1000.0
    calm_ms: NonNeg = 0.0
    low_technologies: tuple[Str, ...] = ("GPRS", "GSM")

    @field_validator("low_technologies")
    @classmethod
    def _technologies(cls, value: tuple[str, ...]) -> tuple[str, ...]:
        check_technologies(value)
        return value

    @model_validator(mode="after")
    def _hysteresis(self):
        if self.to_mbc_below_kbps >= self.to_h264_above_kbps:
            raise ValueError(
                f"to_mbc_below_kbps ({self.to_mbc_below_kbps:g}) must be below "
                f"to_h264_above_kbps ({self.to_h264_above_kbps:g})"
            )
        return self


class EngineConfig(Section):
    """The UMA engine: rate policy by name, full-frame codec and its ladder file, modelled
    compute cost.

    `codec`: the full-frame codec of the rate ladder (a full-frame name of `uma.codecs`);
    `ladder`: its ladder file (None: the codec's own under `codecs/`); `climb`: how the
    throughput policy goes up after `up_hold_ms` (one of `CLIMB_NAMES`); `drained_queue`
    (off, today's behaviour): once every packet sent has been reported, the queueing delay
    the last report measured is taken as drained (0) by the pacer's deadline and uma's skip
    rule, not carried until the next packet measures it (docs/rate-control.md, `rc24`).
    `rung_floor` (on; off is the behaviour before session 25): the skip rule and the backlog
    hold judge a frame at no less than the lowest skippable rung's rate, so an estimate cut
    below that rung (an on/off link's silences) does not hold the sender to the skip limit's
    one frame a second (docs/rate-control.md, `rc26` and "Session 25").
    """

    policy: Str = "throughput"
    codec: Str = "h264"
    ladder: Str | None = None
    safety: Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, le=1)] = 0.85
    up_hold_ms: NonNeg = 1000.0
    climb: Str = "stream"
    drained_queue: Bool = False
    rung_floor: Bool = True
    fixed_rung: NonNegInt | None = None
    transcode_ms: NonNeg = 4.0
    estimator: EstimatorConfig = Field(default_factory=EstimatorConfig)
    switching: SwitchingConfig = Field(default_factory=SwitchingConfig)
    mbc: MbcConfig = Field(default_factory=MbcConfig)
    face_region: FaceRegionConfig = Field(default_factory=FaceRegionConfig)
    pacer: PacerConfig = Field(default_factory=PacerConfig)
    # Tuning (see `uma.engine.engine`): reports missing for this many intervals mean an outage
    # (aiortc's estimate falls);
    # no more than this much sending time in flight; unacknowledged packets presumed lost after
    # this long; while backlogged, a probe frame this often.
    stale_reports: PosInt = 3
    max_backlog_ms: PosNum = 300.0
    presume_lost_ms: PosNum = 2000.0
    probe_interval_ms: PosNum = 1000.0

    @field_validator("policy", "climb")
    @classmethod
    def _named(cls, value: str, info: ValidationInfo) -> str:
        # Plain strings checked here (not Literals) so the message lists the choices.
        names = sorted(POLICY_NAMES) if info.field_name == "policy" else CLIMB_NAMES
        if value not in names:
            raise ValueError(f"expected one of {', '.join(names)}")
        return value

    @model_validator(mode="after")
    def _fixed_needs_rung(self) -> EngineConfig:
        if self.policy == "fixed" and self.fixed_rung is None:
            raise ValueError("policy 'fixed' needs 'fixed_rung'")
        return self

    @field_validator("codec")
    @classmethod
    def _full_frame_codec(cls, value: str) -> str:
        choices = full_frame_names()
        if value not in choices:
            raise ValueError(f"expected a full-frame codec, one of {', '.join(choices)}")
        return value
