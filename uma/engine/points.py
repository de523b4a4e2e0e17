"""The engine's operating points: one ladder across every codec, lowest rate first.

Units: rates in kbit/s, frame rates in frames/s, picture sizes in pixels, compute in ms and
microseconds per cost evaluation.

An operating point names its codec (a name of the registry, `uma.codecs`), the rate it sends,
its frame rate and picture size, and the compute a real engine would spend on one frame there:
`compute_ms` fixed, plus `compute_us_per_evaluation` for each evaluation the codec reports (a
model codec's fitting-cost evaluations when tracking; a region codec counts one per run of its
face detector; a full-frame codec none). The rate ladder the rate policies climb is the
full-frame and region codecs' points (`RATE_CODECS`), ordered by rate (`rate_indices`).
Policies choose an index into the ladder; the world looks the codec up in the registry.
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.codecs import REGISTRY, Role, names

__all__ = [
    "same_stream",
    "continues_stream",
    "OperatingPoint",
    "full_frame_points",
    "role_indices",
    "codec_indices",
    "rate_indices",
    "CODECS",
    "RATE_CODECS",
]

# The codecs a point may name; `uma.sim.codecs` makes an encoder and a decoder for each.
CODECS: tuple[str, ...] = tuple(REGISTRY)
# The codecs of the rate ladder: the region codecs and the full-frame ones.
RATE_CODECS: tuple[str, ...] = names(Role.REGION) + names(Role.FULL_FRAME)


@dataclass(frozen=True)
class OperatingPoint:
    """One thing the engine can send: codec, rate, frame rate, size and modelled compute."""

    codec: str
    rate_kbps: float
    fps: float
    width: int
    height: int
    compute_ms: float = 0.0
    compute_us_per_evaluation: float = 0.0
    label: str = ""

    def __post_init__(self) -> None:
        if self.codec not in CODECS:
            raise ValueError(
                f"operating point: codec one of {', '.join(CODECS)}, got {self.codec!r}"
            )
        if not (self.rate_kbps > 0 and self.fps > 0 and self.width > 0 and self.height > 0):
            raise ValueError(f"operating point {self.label or self.codec}: rate, fps, size > 0")

    def compute_s(self, evaluations: int = 0) -> float:
        """Modelled seconds of engine compute for one frame that cost `evaluations`."""
        return (self.compute_ms + self.compute_us_per_evaluation * evaluations / 1000.0) / 1000.0


def full_frame_points(ladder, *, codec: str, transcode_ms: float) -> tuple[OperatingPoint, ...]:
    """The rungs of `ladder` (`uma.video.Ladder`) as operating points of the full-frame
    `codec`, in its order."""
    return tuple(
        OperatingPoint(
            codec=codec,
            rate_kbps=rung.rate_kbps,
            fps=rung.fps,
            width=rung.width,
            height=rung.height,
            compute_ms=transcode_ms,
            label=f"{codec} {rung.label}",
        )
        for rung in ladder.rungs
    )


def codec_indices(points: tuple[OperatingPoint, ...], codec: str) -> tuple[int, ...]:
    """Indices of the points of `codec`, in ladder order."""
    return tuple(i for i, point in enumerate(points) if point.codec == codec)


def role_indices(points: tuple[OperatingPoint, ...], role: Role) -> tuple[int, ...]:
    """Indices of the points whose codec has `role`, in ladder order."""
    return tuple(i for i, point in enumerate(points) if REGISTRY[point.codec].role is role)


def rate_indices(points: tuple[OperatingPoint, ...]) -> tuple[int, ...]:
    """Indices of the rate ladder's points (`RATE_CODECS`), lowest rate first."""
    family = [i for i, point in enumerate(points) if point.codec in RATE_CODECS]
    return tuple(sorted(family, key=lambda i: (points[i].rate_kbps, i)))


def same_stream(a: OperatingPoint, b: OperatingPoint) -> bool:
    """Whether a change between `a` and `b` keeps one stream: one full-frame codec at one size
    (only the rate or frame rate changes, so the open encoder is retargeted, no keyframe)."""
    full = REGISTRY[a.codec].role is Role.FULL_FRAME
    return full and a.codec == b.codec and (a.width, a.height) == (b.width, b.height)


def continues_stream(points: tuple[OperatingPoint, ...], open_rung: int, rung: int) -> bool:
    """Whether coding at point `rung` continues the stream of the encoder open at `open_rung`
    (-1: none): the same point (any codec, the model codec's parameters too) or one it is
    retargeted to (`same_stream`). Otherwise a new stream starts, with a keyframe."""
    if open_rung < 0:
        return False
    return open_rung == rung or same_stream(points[rung], points[open_rung])
