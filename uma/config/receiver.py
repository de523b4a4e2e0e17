"""The receiver's sections: playout (fixed or adaptive) and the quality metrics it scores.

Units live in key names (`_ms`, `_s`, `_ms_per_s`).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AllowInfNan, Field, Strict

from uma.config.types import Bool, NonNeg, PosNum, Section

__all__ = [
    "AdaptivePlayoutConfig",
    "ReceiverConfig",
    "MetricsConfig",
]


class AdaptivePlayoutConfig(Section):
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


class ReceiverConfig(Section):
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


class MetricsConfig(Section):
    """Which quality metrics to compute for every displayed frame."""

    psnr: Bool = True
    ssim: Bool = True
    # Threads that score frames beside the simulation (0: inline); results do not depend on it.
    workers: Annotated[int, Strict(), Field(ge=0, le=64)] = 2
