"""Pacing: when a frame is held for a backlogged downlink, and the padding the engine sends
behind a coded unit so its bandwidth estimate can grow.

Units: rates in kbit/s, times in seconds, sizes in bits.

Frames are held while more is in flight than `max_backlog_ms` of sending time at the rate the
engine sees (the estimate; the oracle's true capacity, since the estimate it does not use would
call its queue too long). A codec that may not be skipped for backlog (a model codec: its few
kbit/s are below any link the switch chooses it for) is held only while no report came for its
section's `outage_hold_ms`: in an outage its frames would arrive tens of seconds late, while a
handover gap's are still in time.

Padding: a WebRTC encoder sends at its target, uma's ladder at most a rung's rate, and WebRTC's
estimator never rises above 1.5 x what it receives, so with a kind that asks for it
(`RateControl.pads`: aiortc's estimator) each unit is followed by padding up to the estimate's
share of its interval, standing in for the rate a WebRTC encoder would send. The controllers
(`uma`, `gcc`) measure their way up with probes instead (`uma.control.ProbeRequest`).
"""

from __future__ import annotations

from uma.codecs import spec
from uma.engine.inflight import InFlight
from uma.engine.points import OperatingPoint

__all__ = ["backlogged", "padding_bits", "held"]


def backlogged(
    config,
    point: OperatingPoint,
    now_s: float,
    inflight: InFlight,
    seen_kbps: float,
    *,
    queued_bits: int = 0,
) -> bool:
    """Whether a frame at `point` should be held at `now_s` (`config` an `EngineConfig`;
    `seen_kbps` the rate the engine judges the downlink by; `queued_bits` wait in the
    engine's own queue, the pacer's)."""
    codec = spec(point.codec)
    if not codec.skip_for_backlog:
        hold_ms = getattr(config, codec.config_section).outage_hold_ms
        return now_s - inflight.last_report_s > hold_ms / 1000.0
    return inflight.outstanding_bits + queued_bits > seen_kbps * config.max_backlog_ms


def padding_bits(estimate_kbps: float, interval_s: float, *, sent_bits: int) -> float:
    """Bits of padding behind a unit of `sent_bits` covering `interval_s`, so the unit and its
    padding carry the estimate's share (at most 0: the unit already fills it)."""
    return estimate_kbps * 1000.0 * interval_s - sent_bits


def held(
    config, point: OperatingPoint, now_s: float, inflight: InFlight, seen_kbps: float, *,
    queued_bits: int,
) -> bool:  # fmt: skip
    """Hold a frame at `point`: too much in flight (`backlogged`)."""
    return backlogged(config, point, now_s, inflight, seen_kbps, queued_bits=queued_bits)
