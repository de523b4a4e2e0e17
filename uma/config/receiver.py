"""The receiver's sections: playout (fixed or adaptive) and the quality metrics it scores.

Units live in key names (`_ms`, `_s`, `_ms_per_s`).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AllowInfNan, Field, Strict, model_validator

from uma.config.types import Bool, NonNeg, PosNum, Section

__all__ = [
    "AdaptivePlayoutConfig",
    "HandoverPlayoutConfig",
    "ReceiverConfig",
    "MetricsConfig",
]


# A descent of the playout delay, ms per s: below 1000, so display instants never go back in time.
DescentMsPerS = Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, lt=1000)]


class HandoverPlayoutConfig(Section):
    """The adaptive playout's keys within `for_s` of a handover (0: off).

    A handover between two named technologies (a link with none never has one) is a stall of
    known cause, over once the new link carries the queue: within `for_s` of one the playout
    follows these keys instead of its own, a shorter window, a faster descent and a catch-up
    (it returns from the spike) with a wider margin (the new technology's jitter). Chosen on
    the default commute and checked on the real commute; links without named technologies run
    as before (docs/rate-control.md, "Lead, session 21").
    """

    for_s: NonNeg = 20.0
    margin_ms: NonNeg = 100.0
    window_s: PosNum = 1.0
    floor_window_s: PosNum = 0.5
    max_decrease_ms_per_s: DescentMsPerS = 200.0
    catch_up_s: NonNeg = 0.5
    rise_window_s: NonNeg = 0.0


class AdaptivePlayoutConfig(Section):
    """A playout delay that follows the measured frame delay and jitter (`uma.sim.playout`).

    The delay moves towards a target at a bounded slope (down at WebRTC's 100 ms/s, up at most
    500 ms/s by default), within [min_delay_ms, max_delay_ms]. The target is a high percentile
    of the capture-to-decoded delays of the frames decoded in the last `window_s`, plus a
    margin. With `reject_bursts` (off by default), a one-off burst of late frames does not set
    it: a frame later than the path's floor (the least delay of the last `floor_window_s`) by
    more than `outlier_min_ms` and `outlier_jitters` x the jitter (the percentile of the delays
    above the higher of the floor each frame met and the floor now) starts a burst; a burst that
    comes `calm_s` or more after the last late frame (`turbulent_calm_s` if the link was
    turbulent, and from the start) is one-off, and until the next burst the target is the
    higher of floor + jitter and the percentile of the frames outside the burst's episode, and
    the delay does not rise while the floor falls (by `drain_drop_ms` within `drain_window_ms`:
    the burst's queue draining). Late frames closer than `burst_gap_ms` are one burst.
    `catch_up_s` (0: off): above the target, the delay also falls by its excess over the target
    per `catch_up_s` (at most 500 ms/s), so a spike whose cause is gone is not held for
    seconds at 100 ms/s (docs/rate-control.md, rc17); with `catch_up_max` it falls only
    towards the highest delay of the window's frames plus the margin (every one of them, not
    the percentile, must have left the spike). `rise_window_s` (0: off): the delay rises only
    towards the highest delay of the frames decoded in the last `rise_window_s` plus the margin
    (a queue flushed in one burst has been shown by the time the window's percentile asks for
    it). Both off: docs/rate-control.md, "Lead, session 20". `handover`
    (`HandoverPlayoutConfig`): other values of these keys within a while of a handover, the
    receiver's technology changing between two named ones (`during_handover`).
    """

    window_s: PosNum = 2.0
    percentile: Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, le=100)] = 95.0
    margin_ms: NonNeg = 20.0
    min_delay_ms: NonNeg = 50.0
    max_delay_ms: PosNum = 10000.0
    max_decrease_ms_per_s: DescentMsPerS = 100.0
    max_increase_ms_per_s: PosNum = 500.0
    catch_up_s: NonNeg = 0.0
    catch_up_max: Bool = False
    rise_window_s: NonNeg = 0.0
    # Off: measured on the commute and on measured traces (docs/rate-control.md, `rc8`, `rc7`):
    # the commute's p95 falls below 1,000 ms, held-out traces froze 1-2 display instants more.
    reject_bursts: Bool = False
    floor_window_s: PosNum = 1.0
    outlier_min_ms: NonNeg = 150.0
    outlier_jitters: NonNeg = 3.0
    calm_s: NonNeg = 10.0
    turbulent_calm_s: NonNeg = 20.0
    burst_gap_ms: NonNeg = 500.0
    drain_window_ms: PosNum = 250.0
    drain_drop_ms: NonNeg = 100.0
    handover: HandoverPlayoutConfig = Field(default_factory=HandoverPlayoutConfig)

    def during_handover(self) -> AdaptivePlayoutConfig:
        """These keys as the playout follows them within `handover.for_s` of a handover."""
        keys = self.handover.model_dump(exclude={"for_s"})
        return self.model_copy(update=keys)

    @model_validator(mode="after")
    def _handover_within_rules(self) -> AdaptivePlayoutConfig:
        if self.handover.for_s > 0:
            merged = self.during_handover().model_dump()
            merged["handover"] = {"for_s": 0.0}
            try:
                type(self).model_validate(merged)
            except ValueError as err:
                raise ValueError(
                    f"handover: with its keys the playout breaks a rule: {err}"
                ) from None
        return self

    @model_validator(mode="after")
    def _drain_within_window(self) -> AdaptivePlayoutConfig:
        if 2 * self.drain_window_ms > 1000.0 * self.window_s:
            raise ValueError(
                f"drain_window_ms ({self.drain_window_ms:g}) must be at most half of window_s "
                f"({self.window_s:g} s): the floor's fall is read from the window's frames"
            )
        if 2 * self.floor_window_s > self.window_s:
            raise ValueError(
                f"floor_window_s ({self.floor_window_s:g}) must be at most half of window_s "
                f"({self.window_s:g} s): a burst's end compares the floor of two floor windows"
            )
        if self.turbulent_calm_s < self.calm_s:
            raise ValueError(
                f"turbulent_calm_s ({self.turbulent_calm_s:g}) must be at least calm_s "
                f"({self.calm_s:g}): a turbulent link needs at least a calm link's calm"
            )
        return self


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
