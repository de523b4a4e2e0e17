"""The network sections: the uplink, the trace-driven downlink and its route, the feedback path.

Units live in key names (`rate_kbps`, `delay_ms`, `duration_s`, `queue_bytes`).
"""

from __future__ import annotations

from pydantic import Field, field_validator

from uma.config.technologies import check_technologies
from uma.config.types import Fraction, NonNeg, PosInt, PosNum, Section, Str, bounded

__all__ = [
    "UplinkConfig",
    "TechnologyOverride",
    "DownlinkConfig",
    "SegmentConfig",
    "FeedbackConfig",
]


class UplinkConfig(Section):
    """The good sender-to-engine link: fixed rate and delay, no loss."""

    rate_kbps: PosNum = 20000.0
    delay_ms: NonNeg = 20.0


class TechnologyOverride(Section):
    """Per-technology link properties that replace the defaults of `uma.traces`."""

    delay_ms: NonNeg | None = None
    loss_rate: Fraction | None = None


class DownlinkConfig(Section):
    """The trace-driven engine-to-receiver bottleneck."""

    queue_bytes: PosInt = 40000
    # From a small packet to a jumbo frame: each packet is an event of the simulation.
    packet_bytes: bounded(40, 9000, integer=True) = 1200
    handover_gap_ms: NonNeg = 500.0
    technologies: dict[Str, TechnologyOverride] = Field(default_factory=dict)

    @field_validator("technologies")
    @classmethod
    def _technologies(cls, value: dict) -> dict:
        check_technologies(value)
        return value


class SegmentConfig(Section):
    """One stretch of the commute: a technology for a duration, from a trace file or generated."""

    technology: Str
    duration_s: bounded(0, 4 * 3600.0, open_low=True)
    trace: Str | None = None
    format: Str = "auto"
    offset_s: NonNeg = 0.0
    # A trace's rates times this stay below a terabit (`uma.traces` bounds a rate so too).
    scale: bounded(0, 1000.0, open_low=True) = 1.0


class FeedbackConfig(Section):
    """Receiver reports and keyframe requests over the mobile uplink."""

    # A report costs the simulation a few events: more often than every 10 ms (RTCP's
    # transport feedback is every 50-100 ms) a run never ends.
    interval_ms: bounded(10.0, 60_000.0) = 100.0
    keyframe_min_interval_ms: NonNeg = 300.0
    # The uplink's own measured capacity (a Mahimahi `.up` file, read as the route's one
    # segment is, from its `offset_s`): a report waits for it instead of being lost whenever
    # the downlink's capacity is zero. None: the downlink's capacity stands for both ways.
    trace: Str | None = None
    format: Str = "auto"
