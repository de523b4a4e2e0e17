"""The codec registry: what every part of uma needs to know about a codec, looked up by name.

A codec's name is what an operating point, a coded unit, `frames.csv` and `metrics.json` carry.
Everything else about it lives in its `CodecSpec` here, so the engine, the simulated world, the
metrics and the report ask the registry for a trait instead of naming codecs:

- `role`: `FULL_FRAME` codecs code the whole picture at the rungs of a ladder file and are the
  ones `engine.codec` may select; `REGION` codecs are rungs of the same rate ladder that code
  only a region (the face), below the full-frame rungs; a `MODEL` codec needs an
  initialisation on a decoded picture before it can send, and is what switching policies
  switch to at low rates. A codec's *family*, as switching policies see it, is the full-frame
  codec for the whole rate ladder (region rungs included) and the model codec's own name.
- `skip_for_backlog`: the engine may skip a frame when the downlink is backlogged (a model
  codec's few kbit/s are held only while no report comes: `engine.mbc.outage_hold_ms`).
- `fallback`: the role the engine falls back to when the codec reports it cannot code a
  picture (a region codec that finds no face: the lowest full-frame rung; a model codec that
  loses the face: the lowest rung of the rate ladder).
- `config_section`: the `engine.<section>` that configures it (None: its ladder file alone).
  Its operating points are built by its role's builder (`uma.sim.points.BUILDERS`) from that
  section, or for a full-frame codec from its ladder.
- `ladder`: for a full-frame codec, its ladder file under the project's `codecs/` folder.
- `video_encoder`, `video_decoder`: for a full-frame codec, the class names in `uma.video`
  that code it (the interface of `uma.video.H264Encoder` and `uma.video.H264Decoder`).
- `codes_with`: the full-frame codec whose encoder (and ladder file's encoder settings) a
  region codec codes its region with, whatever full-frame codec the run uses.
- `colour`: its colour in plots; `always_reported`: `metrics.json` gives its bits even when a
  run does not use it (the keys every earlier result file has; other codecs' keys appear when
  they are on the run's ladder).
- `uplink`: the sender codes its camera with it (one codec: `uplink_name()`).

Adding a full-frame codec is its classes in `uma.video`, one `CodecSpec` in `REGISTRY`, its
ladder file and its tests (docs/adding-a-codec.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

__all__ = [
    "Role",
    "CodecSpec",
    "REGISTRY",
    "spec",
    "names",
    "full_frame_names",
    "model_names",
    "uplink_name",
    "metric_key",
]


class Role(Enum):
    """What a codec is to the engine."""

    FULL_FRAME = "full-frame"
    REGION = "region"
    MODEL = "model"


@dataclass(frozen=True)
class CodecSpec:
    """One codec's traits (see the module's docstring for each field)."""

    name: str
    role: Role
    label: str
    colour: str
    skip_for_backlog: bool = True
    fallback: Role | None = None
    config_section: str | None = None
    ladder: str | None = None
    video_encoder: str | None = None
    video_decoder: str | None = None
    codes_with: str | None = None
    always_reported: bool = False
    uplink: bool = False

    @property
    def metric_key(self) -> str:
        """The codec's name in metric keys (`kbps_<key>`): a hyphen is an underscore."""
        return metric_key(self.name)


REGISTRY: dict[str, CodecSpec] = {
    spec.name: spec
    for spec in (
        CodecSpec(
            "h264",
            Role.FULL_FRAME,
            label="H.264",
            colour="#1f5fbf",
            ladder="h264.yaml",
            video_encoder="H264Encoder",
            video_decoder="H264Decoder",
            always_reported=True,
            uplink=True,
        ),
        CodecSpec(
            "vp8",
            Role.FULL_FRAME,
            label="VP8",
            colour="#f39c12",
            ladder="vp8.yaml",
            video_encoder="VP8Encoder",
            video_decoder="VP8Decoder",
        ),
        CodecSpec(
            "av1",
            Role.FULL_FRAME,
            label="AV1",
            colour="#6c3483",
            ladder="av1.yaml",
            video_encoder="AV1Encoder",
            video_decoder="AV1Decoder",
        ),
        CodecSpec(
            "h264-face",
            Role.REGION,
            label="H.264 face region",
            colour="#16a085",
            fallback=Role.FULL_FRAME,
            config_section="face_region",
            codes_with="h264",
            always_reported=True,
        ),
        CodecSpec(
            "mbc",
            Role.MODEL,
            label="model-based",
            colour="#c0392b",
            skip_for_backlog=False,
            fallback=Role.FULL_FRAME,
            config_section="mbc",
            always_reported=True,
        ),
    )
}


def spec(name: str) -> CodecSpec:
    """The registered codec `name`; a `KeyError` naming the known ones otherwise."""
    try:
        return REGISTRY[name]
    except KeyError:
        raise KeyError(f"codec: expected one of {', '.join(REGISTRY)}, got {name!r}") from None


def names(role: Role | None = None) -> tuple[str, ...]:
    """The registered codecs (of `role`), in registry order."""
    return tuple(n for n, s in REGISTRY.items() if role is None or s.role is role)


def full_frame_names() -> tuple[str, ...]:
    """The codecs `engine.codec` may select."""
    return names(Role.FULL_FRAME)


def model_names() -> tuple[str, ...]:
    return names(Role.MODEL)


def uplink_name() -> str:
    """The full-frame codec the sender codes its camera with over the good uplink."""
    return next(n for n, s in REGISTRY.items() if s.uplink)


def metric_key(name: str) -> str:
    """`name` as it appears in a metric key (`kbps_h264_face`)."""
    return name.replace("-", "_")
