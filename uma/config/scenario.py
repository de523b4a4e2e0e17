"""The scenario schema: one YAML file parsed once into frozen, validated objects.

Units live in key names (`rate_kbps`, `delay_ms`, `duration_s`, `queue_bytes`). Numbers must be
numbers (a string such as "2 Mbit/s" is refused, so a unit cannot hide in a value), unknown keys
are refused, and relative paths are resolved against the scenario file's folder when loaded, so
the resolved scenario written beside the results repeats the run from anywhere.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

from pydantic import (
    AllowInfNan,
    BaseModel,
    ConfigDict,
    Field,
    Strict,
    field_validator,
    model_validator,
)

from uma.codecs import full_frame_names

__all__ = [
    "Scenario",
    "SourceConfig",
    "SenderConfig",
    "UplinkConfig",
    "DownlinkConfig",
    "TechnologyOverride",
    "SegmentConfig",
    "FeedbackConfig",
    "EstimatorConfig",
    "EngineConfig",
    "ReceiverConfig",
    "AdaptivePlayoutConfig",
    "MetricsConfig",
    "POLICY_NAMES",
    "FaultsConfig",
    "LossBurstConfig",
    "OutageConfig",
    "ReorderConfig",
    "SilenceConfig",
    "ESTIMATOR_KINDS",
    "SwitchingConfig",
    "MbcConfig",
    "FaceRegionConfig",
    "FaceRungConfig",
    "SWITCHING_NAMES",
]

# The rate policies `engine.policy` may name; `uma.engine.policy.POLICIES` implements each.
POLICY_NAMES: tuple[str, ...] = ("throughput", "oracle", "fixed")
# Bandwidth estimators the engine can use: its own delay-based one, or WebRTC's receiver-side
# estimator (aiortc's port of webrtc.org's RemoteBitrateEstimator) carried back as a REMB.
ESTIMATOR_KINDS = ("uma", "webrtc")
# Switching policies `engine.switching.policy` may name (`uma.engine.policy.SWITCHING`).
SWITCHING_NAMES: tuple[str, ...] = ("none", "threshold", "predictive")

Num = Annotated[float, Strict(), AllowInfNan(False)]
PosNum = Annotated[float, Strict(), AllowInfNan(False), Field(gt=0)]
NonNeg = Annotated[float, Strict(), AllowInfNan(False), Field(ge=0)]
Fraction = Annotated[float, Strict(), AllowInfNan(False), Field(ge=0, le=1)]
PosInt = Annotated[int, Strict(), Field(gt=0)]
NonNegInt = Annotated[int, Strict(), Field(ge=0)]
Bool = Annotated[bool, Strict()]
Str = Annotated[str, Strict()]


class _Section(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")


class SourceConfig(_Section):
    """What the sender captures: a video file, raw YUV 4:2:0, or a built-in synthetic source."""

    kind: Literal["pattern", "file", "yuv", "talking-head"] = "pattern"
    path: Str | None = None
    width: PosInt = 352
    height: PosInt = 288
    fps: PosNum = 25.0
    loop: Bool = True

    @model_validator(mode="after")
    def _path_needed(self) -> SourceConfig:
        if self.kind in ("file", "yuv") and not self.path:
            raise ValueError(f"source kind '{self.kind}' needs 'path' (a video file)")
        if self.width % 2 or self.height % 2:
            raise ValueError(
                f"width and height must be even for 4:2:0, got {self.width}x{self.height}"
            )
        return self


class SenderConfig(_Section):
    """The sender's own H.264 encoding, at a high rate over the good uplink."""

    rate_kbps: PosNum = 1500.0
    preset: Str = "ultrafast"
    keyint_frames: PosInt = 250


class UplinkConfig(_Section):
    """The good sender-to-engine link: fixed rate and delay, no loss."""

    rate_kbps: PosNum = 20000.0
    delay_ms: NonNeg = 20.0


class TechnologyOverride(_Section):
    """Per-technology link properties that replace the defaults of `uma.traces`."""

    delay_ms: NonNeg | None = None
    loss_rate: Fraction | None = None


class DownlinkConfig(_Section):
    """The trace-driven engine-to-receiver bottleneck."""

    queue_bytes: PosInt = 40000
    packet_bytes: PosInt = 1200
    handover_gap_ms: NonNeg = 500.0
    technologies: dict[Str, TechnologyOverride] = Field(default_factory=dict)


class SegmentConfig(_Section):
    """One stretch of the commute: a technology for a duration, from a trace file or generated."""

    technology: Str
    duration_s: PosNum
    trace: Str | None = None
    format: Str = "auto"
    offset_s: NonNeg = 0.0
    scale: PosNum = 1.0


class FeedbackConfig(_Section):
    """Receiver reports and keyframe requests over the mobile uplink."""

    interval_ms: PosNum = 100.0
    keyframe_min_interval_ms: NonNeg = 300.0


class EstimatorConfig(_Section):
    """The engine's delay-based bandwidth estimator (see `uma.engine.estimator`)."""

    initial_kbps: PosNum = 300.0
    min_kbps: PosNum = 5.0
    max_kbps: PosNum = 20000.0
    queue_high_ms: PosNum = 150.0
    queue_low_ms: PosNum = 40.0
    decrease_factor: Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, lt=1)] = 0.85
    increase_per_s: NonNeg = 0.5
    loss_high: Fraction = 0.1
    window_s: PosNum = 1.0
    # Decrease once per window (not per queue-drain time) while the received rate is below
    # this fraction of the estimate; 0 turns it off.
    collapse_below: Fraction = 0.25
    # Which estimator: `engine.estimator: webrtc` is short for `engine.estimator: {kind: webrtc}`.
    kind: Literal["uma", "webrtc"] = "uma"

    @model_validator(mode="before")
    @classmethod
    def _kind_shorthand(cls, data):
        if isinstance(data, str):
            if data not in ESTIMATOR_KINDS:
                raise ValueError(f"expected one of {', '.join(ESTIMATOR_KINDS)}")
            return {"kind": data}
        return data


class SwitchingConfig(_Section):
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
    """

    policy: Literal["none", "threshold", "predictive", "oracle"] = "none"
    to_mbc_below_kbps: PosNum = 30.0
    to_h264_above_kbps: PosNum = 60.0
    min_dwell_ms: NonNeg = 3000.0
    retry_ms: PosNum = 5000.0
    lookahead_ms: NonNeg = 3000.0
    oracle_lookahead_ms: NonNeg = 1000.0
    low_technologies: tuple[Str, ...] = ("GPRS", "GSM")

    @model_validator(mode="after")
    def _hysteresis(self):
        if self.to_mbc_below_kbps >= self.to_h264_above_kbps:
            raise ValueError(
                f"to_mbc_below_kbps ({self.to_mbc_below_kbps:g}) must be below "
                f"to_h264_above_kbps ({self.to_h264_above_kbps:g})"
            )
        return self


class MbcConfig(_Section):
    """The model-based codec in the engine: the content description and modelled compute.

    `description`: a file written by `uma describe` (relative to the scenario), or a points
    file such as `codecs/face/akiyo.yaml`, from which the description is fitted when the run
    starts; the talking head needs none (its description is the astronaut's). Compute is
    modelled from the tracker's count of fitting-cost evaluations: `init_us_per_evaluation`
    for an initialisation (detector, SAABs, polish), `track_us_per_evaluation` for a tracking
    step, plus `encode_ms` per frame (quantise, range-code). Defaults measured on this machine in
    CPU time by `python -m uma.bench.mbc_cost` (talking head at CIF, seed 2, 120 frames,
    re-initialised every 30; CPU time because the machine was shared, load about 9 on 2
    cores, and wall time read 2.5x more): medians 143 us per evaluation over 4
    initialisations (651 evaluations, 93 ms) and 1,021 us over 116 tracking steps (7
    evaluations, 7.2 ms).
    `rate_kbps` is the point's nominal rate on the ladder (on the wire), `fps` its frame rate;
    `frames_per_packet` frames go in one packet (one packet a frame at 25 frames/s would spend
    8 kbit/s on the 40 header bytes alone, nearly GSM's whole 9.6).
    `deliver_description`: send the description to the receiver ahead of need, in packets
    sharing the downlink with the video when the estimate leaves room (false: the receiver is
    assumed to hold it), using the room the estimate leaves above the point's rate but at least
    `description_share` of the estimate; MBC is used only once a receiver report confirms it.
    `probe`: while on MBC, follow each parameter packet with padding up to the estimate's
    share of the frame interval, so the estimate can grow back (without it, it stays within
    3 x the parameters' few kbit/s and the engine never returns to H.264).
    """

    description: Str | None = None
    rate_kbps: PosNum = 4.8
    fps: PosNum = 25.0
    frames_per_packet: Annotated[int, Strict(), Field(ge=1, le=255)] = 4
    init_us_per_evaluation: PosNum = 143.0
    track_us_per_evaluation: PosNum = 1021.0
    encode_ms: NonNeg = 0.2
    probe: Bool = True
    deliver_description: Bool = True
    description_share: Fraction = 0.1
    # Hold MBC frames (but a probe every `engine.probe_interval_ms`) while no receiver report
    # has come for this long: the link is out, and what is sent would queue until it returns.
    outage_hold_ms: PosNum = 1000.0
    # The customisation scheme: `adaptation` (the sender sends H.264 only; the engine tracks
    # the face in what it decodes, and initialises on a switch) or `selection` (the sender
    # tracks the face in every frame and sends its parameters up with the H.264; the engine
    # only selects, and re-codes them for the downlink).
    scheme: Literal["adaptation", "selection"] = "adaptation"


class FaceRungConfig(_Section):
    """One face-region rung: the H.264 rate (on the wire, header included), the coded size
    of the face crop in pixels (even) and the frame rate."""

    rate_kbps: PosNum
    width: PosInt
    height: PosInt
    fps: PosNum

    @model_validator(mode="after")
    def _even(self) -> FaceRungConfig:
        if self.width % 2 or self.height % 2 or self.width < 16 or self.height < 16:
            raise ValueError(
                f"width and height must be even and at least 16, got {self.width}x{self.height}"
            )
        return self


class FaceRegionConfig(_Section):
    """Object-level adaptation: rungs that code only the face region (`uma.sim.face_region`).

    `enabled`: put `rungs` on the rate ladder, below the lowest full-frame H.264 rung (their
    rates must be lower; checked against the ladder file when the run starts). The crop is
    the detected face box widened by `margin` of its size on each side, shaped like the rung's
    coded size; the detector (OpenCV's Haar cascade on the engine's decoded picture, scaled to
    at most 176 pixels wide) runs on a rung's first frame and then every
    `detect_every_frames` source frames, its box centre smoothed with weight `smoothing` on
    the new detection. `detect_us_per_pixel` models the detector's compute per pixel it
    scans; default measured on this machine by `python -m uma.bench.face_rung --cost`
    (CPU time on the shared machine, 60 frames each: akiyo 0.84, carphone 0.69, the QCIF
    talking head 0.82 us per pixel, 21.3, 17.4 and 20.7 ms a detection; the median, 0.82).
    The rungs' defaults were chosen on carphone (README, "Object-level adaptation").
    With no face found, the engine leaves the face rungs for the lowest full-frame rung for
    `retry_ms` and says why in its events.
    """

    enabled: Bool = False
    rungs: tuple[FaceRungConfig, ...] = (
        FaceRungConfig(rate_kbps=8.0, width=48, height=48, fps=5.0),
        FaceRungConfig(rate_kbps=12.0, width=48, height=48, fps=5.0),
    )
    margin: Annotated[float, Strict(), AllowInfNan(False), Field(ge=0, le=1)] = 0.2
    detect_every_frames: PosInt = 25
    smoothing: Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, le=1)] = 0.5
    detect_us_per_pixel: PosNum = 0.82
    retry_ms: PosNum = 5000.0

    @model_validator(mode="after")
    def _rungs(self) -> FaceRegionConfig:
        if self.enabled and not self.rungs:
            raise ValueError("rungs: expected at least one face-region rung when enabled")
        rates = [rung.rate_kbps for rung in self.rungs]
        if rates != sorted(set(rates)):
            raise ValueError(f"rungs: expected rates strictly increasing, got {rates}")
        return self


class EngineConfig(_Section):
    """The UMA engine: rate policy by name, full-frame codec and its ladder file, modelled
    compute cost.

    `codec`: the full-frame codec of the rate ladder (a full-frame name of `uma.codecs`);
    `ladder`: its ladder file (None: the codec's own under `codecs/`).
    """

    policy: Str = "throughput"
    codec: Str = "h264"
    ladder: Str | None = None
    safety: Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, le=1)] = 0.85
    up_hold_ms: NonNeg = 1000.0
    fixed_rung: NonNegInt | None = None
    transcode_ms: NonNeg = 4.0
    estimator: EstimatorConfig = Field(default_factory=EstimatorConfig)
    switching: SwitchingConfig = Field(default_factory=SwitchingConfig)
    mbc: MbcConfig = Field(default_factory=MbcConfig)
    face_region: FaceRegionConfig = Field(default_factory=FaceRegionConfig)
    # Tuning (see `uma.engine.engine`): reports missing for this many intervals mean an outage;
    # no more than this much sending time in flight; unacknowledged packets presumed lost after
    # this long; while backlogged, a probe frame this often.
    stale_reports: PosInt = 3
    max_backlog_ms: PosNum = 300.0
    presume_lost_ms: PosNum = 2000.0
    probe_interval_ms: PosNum = 1000.0

    @field_validator("codec")
    @classmethod
    def _full_frame_codec(cls, value: str) -> str:
        choices = full_frame_names()
        if value not in choices:
            raise ValueError(f"expected a full-frame codec, one of {', '.join(choices)}")
        return value


class AdaptivePlayoutConfig(_Section):
    """A playout delay that follows the measured frame delay and jitter (`uma.sim.playout`).

    The target is a high percentile of the capture-to-decoded delays of the frames decoded in
    the last `window_s`, plus a margin, within [min_delay_ms, max_delay_ms]; the delay moves
    towards it at a bounded slope (down at WebRTC's 100 ms/s, up at most 500 ms/s by default).
    """

    window_s: PosNum = 2.0
    percentile: Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, le=100)] = 95.0
    margin_ms: NonNeg = 20.0
    min_delay_ms: NonNeg = 50.0
    max_delay_ms: PosNum = 10000.0
    # Below 1000 ms/s, so display instants never go back in time.
    max_decrease_ms_per_s: Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, lt=1000)] = (
        100.0
    )
    max_increase_ms_per_s: PosNum = 500.0


class ReceiverConfig(_Section):
    """The mobile receiver's playout: a fixed conversational deadline, or adaptive."""

    playout_delay_ms: PosNum = 300.0
    # Tuning (see `uma.sim.receiver`): ask again for an IDR when none came this long after the
    # last request; one-way delays older than this no longer set the queue-delay base.
    keyframe_retry_ms: PosNum = 1000.0
    base_delay_window_s: PosNum = 10.0
    # `fixed`: every frame at capture + playout_delay_ms; `adaptive`: the delay starts at
    # playout_delay_ms and then follows the frames' delays as `adaptive` says.
    playout: Literal["fixed", "adaptive"] = "fixed"
    adaptive: AdaptivePlayoutConfig = Field(default_factory=AdaptivePlayoutConfig)


class MetricsConfig(_Section):
    """Which quality metrics to compute for every displayed frame."""

    psnr: Bool = True
    ssim: Bool = True
    # Threads that score frames beside the simulation (0: inline); results do not depend on it.
    workers: NonNegInt = 2


class LossBurstConfig(_Section):
    """Gilbert-Elliott loss bursts: a good and a bad state, stepped once per packet leaving the
    downlink; a packet is lost with the state's probability (on top of the random loss)."""

    p_good_to_bad: Fraction = 0.01
    p_bad_to_good: Fraction = 0.3
    loss_good: Fraction = 0.0
    loss_bad: Fraction = 1.0


class OutageConfig(_Section):
    """Zero downlink capacity from `start_s` for `duration_s` (it may outlast the run)."""

    start_s: NonNeg
    duration_s: PosNum


class ReorderConfig(_Section):
    """Each packet, with `probability`, arrives `delay_ms` late and is overtaken by later ones."""

    probability: Fraction = 0.05
    delay_ms: PosNum = 50.0


class SilenceConfig(_Section):
    """The feedback channel (reports, keyframe requests) carries nothing for a stretch."""

    start_s: NonNeg
    duration_s: PosNum


class FaultsConfig(_Section):
    """Link faults injected into the run (see `uma.sim.faults`); none by default."""

    loss_bursts: LossBurstConfig | None = None
    outages: tuple[OutageConfig, ...] = ()
    reorder: ReorderConfig | None = None
    feedback_silence: tuple[SilenceConfig, ...] = ()


class Scenario(_Section):
    """A whole experiment; `Scenario.load(path)` is the way in (`uma.config.load_scenario`)."""

    name: Annotated[str, Strict(), Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")]
    description: Str = ""
    seed: NonNegInt = 0
    duration_s: PosNum | None = None
    source: SourceConfig = Field(default_factory=SourceConfig)
    sender: SenderConfig = Field(default_factory=SenderConfig)
    uplink: UplinkConfig = Field(default_factory=UplinkConfig)
    downlink: DownlinkConfig = Field(default_factory=DownlinkConfig)
    route: tuple[SegmentConfig, ...] = Field(min_length=1)
    feedback: FeedbackConfig = Field(default_factory=FeedbackConfig)
    engine: EngineConfig = Field(default_factory=EngineConfig)
    receiver: ReceiverConfig = Field(default_factory=ReceiverConfig)
    metrics: MetricsConfig = Field(default_factory=MetricsConfig)
    faults: FaultsConfig = Field(default_factory=FaultsConfig)

    @property
    def route_duration_s(self) -> float:
        return sum(segment.duration_s for segment in self.route)

    @property
    def run_duration_s(self) -> float:
        """Simulated capture time: `duration_s`, or the whole route when not given."""
        return self.duration_s if self.duration_s is not None else self.route_duration_s

    def resolved_paths(self, base_dir: Path) -> Scenario:
        """A copy whose relative file paths are made absolute against `base_dir`."""

        def absolute(path: str | None) -> str | None:
            if path is None:
                return None
            candidate = Path(path).expanduser()
            return str(candidate if candidate.is_absolute() else (base_dir / candidate).resolve())

        route = tuple(
            segment.model_copy(update={"trace": absolute(segment.trace)}) for segment in self.route
        )
        source = self.source.model_copy(update={"path": absolute(self.source.path)})
        mbc = self.engine.mbc.model_copy(
            update={"description": absolute(self.engine.mbc.description)}
        )
        engine = self.engine.model_copy(update={"ladder": absolute(self.engine.ladder), "mbc": mbc})
        return self.model_copy(update={"route": route, "source": source, "engine": engine})

    def with_seed(self, seed: int) -> Scenario:
        return self.model_copy(update={"seed": seed})
