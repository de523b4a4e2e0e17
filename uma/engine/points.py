"""The engine's operating points: one ladder across every codec, lowest rate first.

Units: rates in kbit/s, frame rates in frames/s, picture sizes in pixels, compute in ms and
microseconds per cost evaluation.

An operating point names its codec (`h264`, `h264-face`, `mbc`), the rate it sends, its frame rate and picture
size, and the compute a real engine would spend on one frame there: `compute_ms` fixed, plus
`compute_us_per_evaluation` for each evaluation the codec reports (MBC's fitting-cost
evaluations when tracking; `h264-face` counts one per run of its face detector; H.264 none).
The rate ladder the rate policies climb is the family `RATE_CODECS` (the face-region rungs and
the full-frame H.264 rungs), ordered by rate (`rate_indices`). Policies choose an index into the ladder; the world looks the
codec up by name in its registry. Adding a codec is a codec module, a registry entry and points.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "OperatingPoint",
    "h264_points",
    "codec_indices",
    "rate_indices",
    "CODECS",
    "RATE_CODECS",
]

# The codecs a point may name; `uma.sim.codecs` registers an encoder and a decoder for each.
CODECS: tuple[str, ...] = ("h264", "h264-face", "mbc")
# The codecs of the rate ladder: H.264 of the face region only, and of the whole frame.
RATE_CODECS: tuple[str, ...] = ("h264-face", "h264")


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


def h264_points(ladder, *, transcode_ms: float) -> tuple[OperatingPoint, ...]:
    """The H.264 rungs of `ladder` (`uma.video.Ladder`) as operating points, in its order."""
    return tuple(
        OperatingPoint(
            codec="h264",
            rate_kbps=rung.rate_kbps,
            fps=rung.fps,
            width=rung.width,
            height=rung.height,
            compute_ms=transcode_ms,
            label=f"h264 {rung.label}",
        )
        for rung in ladder.rungs
    )


def codec_indices(points: tuple[OperatingPoint, ...], codec: str) -> tuple[int, ...]:
    """Indices of the points of `codec`, in ladder order."""
    return tuple(i for i, point in enumerate(points) if point.codec == codec)


def rate_indices(points: tuple[OperatingPoint, ...]) -> tuple[int, ...]:
    """Indices of the rate ladder's points (`RATE_CODECS`), lowest rate first."""
    family = [i for i, point in enumerate(points) if point.codec in RATE_CODECS]
    return tuple(sorted(family, key=lambda i: (points[i].rate_kbps, i)))
