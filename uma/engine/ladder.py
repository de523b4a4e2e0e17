"""The engine's ladder: the rate rungs, the region rungs among them, the model codec's point,
and frame decimation.

Units: rates in kbit/s, frame rates in frames/s, times in seconds.

The rate ladder (`rate`) is every full-frame and region point, lowest rate first: the rate
policies climb it. Region rungs can be taken off it for a while (`block_regions`: the region
codec found no face), leaving the full-frame rungs (`full_frame`). A point's family, as the
switching policies see it, is the full-frame codec's name for the whole rate ladder and the
model codec's own name for its point.
"""

from __future__ import annotations

from uma.codecs import Role, spec
from uma.engine.points import OperatingPoint, codec_indices, rate_indices, role_indices

__all__ = ["Ladder"]


class Ladder:
    """Indices into `points` by role, and which of them are allowed now."""

    def __init__(
        self, points: tuple[OperatingPoint, ...], *, codec: str, source_fps: float
    ) -> None:
        self.points = points
        self.codec = codec  # the full-frame codec: the rate ladder's family
        self.source_fps = source_fps
        self.rate = rate_indices(points)
        self.full_frame = codec_indices(points, codec) or self.rate
        model = role_indices(points, Role.MODEL)
        self.model_point = model[0] if model else None
        self.model_codec = points[model[0]].codec if model else None
        self.regions_blocked_until_s = float("-inf")

    def initial(self, config, estimate_kbps: float) -> int:
        """The rung to start on (`config` an `EngineConfig`): the fixed policy's, or the highest
        whose rate fits safety x the initial estimate."""
        from uma.engine.policy import highest_fitting

        if config.policy == "fixed" and config.fixed_rung is not None:
            return self.rate[min(config.fixed_rung, len(self.rate) - 1)]
        rates = tuple(self.points[i].rate_kbps for i in self.rate)
        return self.rate[highest_fitting(rates, config.safety * estimate_kbps)]

    def allowed(self, now_s: float) -> tuple[int, ...]:
        """The rate ladder now: without the region rungs while they are blocked."""
        return self.full_frame if now_s < self.regions_blocked_until_s else self.rate

    def block_regions(self, until_s: float) -> None:
        self.regions_blocked_until_s = until_s

    def role(self, index: int) -> Role:
        return spec(self.points[index].codec).role

    def family(self, index: int) -> str:
        """The family of point `index`: the model codec's name, or the rate ladder's codec."""
        return self.points[index].codec if self.role(index) is Role.MODEL else self.codec

    def scheduled(self, frame: int, index: int) -> bool:
        """Whether point `index`'s frame rate keeps source frame `frame`."""
        # Keep frame i when the point's frame clock ticks between i and i + 1 of the source's.
        ratio = min(1.0, self.points[index].fps / self.source_fps)
        return int((frame + 1) * ratio + 1e-9) > int(frame * ratio + 1e-9)
