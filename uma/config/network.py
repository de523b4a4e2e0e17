"""The network sections: the uplink, the trace-driven downlink and its route, the feedback path.

Units live in key names (`rate_kbps`, `delay_ms`, `duration_s`, `queue_bytes`).
"""

from __future__ import annotations

from pydantic import Field

from uma.config.types import Fraction, NonNeg, PosInt, PosNum, Section, Str

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
    packet_bytes: PosInt = 1200
    handover_gap_ms: NonNeg = 500.0
    technologies: dict[Str, TechnologyOverride] = Field(default_factory=dict)


class SegmentConfig(Section):
    """One stretch of the commute: a technology for a duration, from a trace file or generated."""

    technology: Str
    duration_s: PosNum
    trace: Str | None = None
    format: Str = "auto"
    offset_s: NonNeg = 0.0
    scale: PosNum = 1.0


class FeedbackConfig(Section):
    """Receiver reports and keyframe requests over the mobile uplink."""

    interval_ms: PosNum = 100.0
    keyframe_min_interval_ms: NonNeg = 300.0
