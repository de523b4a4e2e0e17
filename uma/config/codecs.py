"""The codec sections of `engine`: the model-based codec (`engine.mbc`) and the face-region
rungs (`engine.face_region`), each named by its codec's `config_section` in `uma.codecs`.

Units live in key names (`rate_kbps`, `_ms`, `_us_per_evaluation`, pixels for sizes).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AllowInfNan, Field, Strict, model_validator

from uma.config.types import Bool, Fraction, NonNeg, Num, PosInt, PosNum, Section, Str

__all__ = [
    "MbcConfig",
    "RefreshConfig",
    "FaceRungConfig",
    "FaceRegionConfig",
]


# libx264's presets a refresh may use (`uma.video.PRESETS` up to `slow`).
RefreshPreset = Literal["ultrafast", "superfast", "veryfast", "faster", "fast", "medium", "slow"]
# The scene mesh's rings (`uma.mbc.scene_render`): beyond 8 radii a ring lies far outside any
# picture, and its coordinates overflow the renderer's integers near 1e5.
RingSize = Annotated[float, Strict(), AllowInfNan(False), Field(gt=1, le=8)]
Fps = Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, le=120)]
FrameBits = Annotated[int, Strict(), Field(ge=1000, le=100_000_000)]
Interval = Annotated[float, Strict(), AllowInfNan(False), Field(ge=40, le=3_600_000)]


class RefreshConfig(Section):
    """The model-aided refresh (`engine.mbc.refresh`, docs/refresh.md): while on the model
    codec, the rate the budget leaves above its point's (`safety` x estimate - `rate_kbps`)
    carries a low-frame-rate H.264 stream of a box around the face (1.6 x the model's extent,
    coded at half size: `uma.mbc.RefreshCoder`) beside the parameters, and the receiver takes
    each refresh it decodes into its reference (`uma.mbc.take_refresh`, at that frame's
    decoded pose).

    An intra refresh starts a stream sized to what `share` of the spare rate carries in
    `interval_ms` (within `min_frame_bits` and `max_frame_bits`; libx264 at that many bits a
    frame, its VBV one frame); the refreshes after it are predicted from the one before at
    that size. The spare rate sets how often: the next refresh is coded once the last one has
    left and its own bits at `share` of the spare rate would have taken as long, never sooner
    than `min_interval_ms` after it, and none while that would take more than
    `max_interval_ms` or less than `min_spare_kbps` are spare. Its packets (`packet_bytes` of
    payload) leave at the spare rate (at least half `min_spare_kbps`), none while the last
    report's queueing delay is more than `queue_high_ms` above its least over the last
    `queue_window_ms` (they would delay the parameters behind them). The
    first refresh of a stretch on the model codec, the one after a lost refresh and the one
    after the spare rate has doubled the stream's size are intra. `face`: where the rendered face's
    own triangles come from once a refresh is the reference: the refresh picture itself
    (`picture`), the description's texture (`description`), or the refresh picture's for
    `face_recent_ms` after its frame and the description's after that (`recent`: a head that
    moved far from the refresh's pose is drawn better from the exact description). `preset`:
    libx264's (a picture
    every interval, so a slower preset than the ladder's costs little). A refresh is sent only
    when, over the face box, it beats by `min_gain_db` what the engine's mirror of the
    receiver renders at that frame (a sharp old reference of a still scene can be better than
    a small refresh); else it is not sent and the next one starts intra. With `first_always`
    the first refresh of a stretch skips that check (the mirror is then the engine's own
    initialisation picture, often sharper than the receiver's last one; measured on the akiyo
    cut of docs/refresh.md, checking it too did better). `encode_ms`: the
    modelled compute of coding one refresh, decoding it again for the mirror and that check.
    `handover_drain_ms`: when the reports name a new technology, a refresh under way whose
    remaining bits would take longer than this at the new estimate is dropped (the next intra).
    """

    enabled: Bool = False
    interval_ms: Interval = 1000.0
    min_frame_bits: FrameBits = 8000
    max_frame_bits: FrameBits = 32000
    min_interval_ms: Interval = 400.0
    max_interval_ms: Interval = 3000.0
    min_spare_kbps: PosNum = 10.0
    share: Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, le=1)] = 0.8
    queue_high_ms: PosNum = 100.0
    queue_window_ms: PosNum = 2000.0
    packet_bytes: Annotated[int, Strict(), Field(ge=100, le=1500)] = 500
    face: Literal["recent", "picture", "description"] = "recent"
    face_recent_ms: NonNeg = 2000.0
    preset: RefreshPreset = "medium"
    min_gain_db: Num = 0.5
    first_always: Bool = False
    encode_ms: NonNeg = 12.0
    handover_drain_ms: PosNum = 500.0

    @model_validator(mode="after")
    def _intervals(self) -> RefreshConfig:
        if self.min_frame_bits > self.max_frame_bits:
            raise ValueError(
                f"min_frame_bits ({self.min_frame_bits}) must not exceed max_frame_bits "
                f"({self.max_frame_bits})"
            )
        if self.min_interval_ms > self.max_interval_ms:
            raise ValueError(
                f"min_interval_ms ({self.min_interval_ms:g}) must not exceed max_interval_ms "
                f"({self.max_interval_ms:g})"
            )
        return self


class MbcConfig(Section):
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
    8 kbit/s on the 40 header bytes alone, nearly GSM's whole 9.6); a packet starts with an
    intra set at least every `intra_period_frames` frames (at least `frames_per_packet`; the
    other sets predict from the one before, and a lost packet leaves the receiver on its last
    set until the next intra one, or the one it asks for). The default, every packet, costs
    the most bits and loses only a lost packet's frames (docs/switching.md, "The parameter
    stream's intra period").
    `deliver_description`: send the description to the receiver ahead of need, in packets
    sharing the downlink with the video when the estimate leaves room (false: the receiver is
    assumed to hold it), using the room the estimate leaves above the point's rate but at least
    `description_share` of the estimate; MBC is used only once a receiver report confirms it.
    `light`: code the face's light (gain and offset) in every parameter set and relight the
    rendering by it; `light_ms`: its modelled compute per frame (the encoder renders the face
    and fits the light). `far_ring_head_radii`, `head_ring_outlines`: the renderer's scene
    mesh (`uma.mbc.scene_render`): the far ring, fixed in the picture, in head-ring radii from
    the face's centre, and the head ring (moves with the head) in face-outline radii, unless
    the description carries its sender's choice (`uma.mbc.profile.with_sender_ring`);
    `soften_outline`: where that choice is the tighter ring (the pose is off at the outline),
    blend a band about the drawn head's outline toward its blur as the head moves from the
    reference (`uma.mbc.outline`). `uma bench mbc` renders with these (`uma.mbc.profile`);
    docs/mbc.md (session mbc5) has the measurements that chose them.
    `refresh`: the model-aided refresh (`RefreshConfig`).
    """

    description: Str | None = None
    rate_kbps: PosNum = 4.8
    fps: Fps = 25.0
    frames_per_packet: Annotated[int, Strict(), Field(ge=1, le=255)] = 4
    intra_period_frames: Annotated[int, Strict(), Field(ge=1, le=10000)] = 4
    init_us_per_evaluation: PosNum = 143.0
    track_us_per_evaluation: PosNum = 1021.0
    encode_ms: NonNeg = 0.2
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
    light: Bool = True
    light_ms: NonNeg = 1.5
    far_ring_head_radii: RingSize = 1.6
    head_ring_outlines: RingSize = 1.4
    soften_outline: Bool = True
    refresh: RefreshConfig = Field(default_factory=RefreshConfig)

    @model_validator(mode="after")
    def _intra_period(self) -> MbcConfig:
        if self.intra_period_frames < self.frames_per_packet:
            raise ValueError(
                f"intra_period_frames ({self.intra_period_frames}) must be at least "
                f"frames_per_packet ({self.frames_per_packet})"
            )
        return self


class FaceRungConfig(Section):
    """One face-region rung: the H.264 rate (on the wire, header included), the coded size
    of the face crop in pixels (even) and the frame rate."""

    rate_kbps: PosNum
    width: Annotated[int, Strict(), Field(gt=0, le=4096)]
    height: Annotated[int, Strict(), Field(gt=0, le=4096)]
    fps: Fps

    @model_validator(mode="after")
    def _even(self) -> FaceRungConfig:
        if self.width % 2 or self.height % 2 or self.width < 16 or self.height < 16:
            raise ValueError(
                f"width and height must be even and at least 16, got {self.width}x{self.height}"
            )
        return self


class FaceRegionConfig(Section):
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
