"""Pacing: when a frame is held for a backlogged downlink, and the padding the engine sends
behind a coded unit so its bandwidth estimate can grow.

Units: rates in kbit/s, times in seconds, sizes in bits.

Frames are held while more is in flight than `max_backlog_ms` of sending time at the rate the
engine sees (the estimate; the oracle's true capacity, since the estimate it does not use would
call its queue too long). A codec that may not be skipped for backlog (a model codec: its few
kbit/s are below any link the switch chooses it for) is held only while no report came for its
section's `outage_hold_ms`: in an outage its frames would arrive tens of seconds late, while a
handover gap's are still in time.

With `engine.frame_fit` on (and the pacer), a frame is also held when it would not drain
before the next frame (`frame_fits`).

Two reasons to pad. With WebRTC's estimator (`engine.estimator: webrtc`): a WebRTC sender
encodes at its target rate, uma's ladder sends at most a rung's rate, and WebRTC's estimator
never rises above 1.5 x what it receives, so without padding it could never climb to the next
rung; the padding stands in for the rate a WebRTC encoder would send. On a model codec with
its section's `probe` on: its parameters alone (a few kbit/s) would cap the estimate at 3 x
that, and padding lets it find the bandwidth to return (the oracle needs no probe); only up
to safety x the estimate, no further than the rate that would bring the engine back to the
rate ladder, and only while the last report saw no queue: padding shares the bottleneck's
queue with the parameters, and padding into a queue delays them behind it and overflows it.
"""

from __future__ import annotations

from uma.codecs import Role, spec
from uma.engine.inflight import InFlight
from uma.engine.points import OperatingPoint

__all__ = ["backlogged", "padding_bits", "frame_fits", "held"]


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


def frame_fits(
    point: OperatingPoint, *, queued_bits: int, rate_kbps: float, fps: float, slack_frames: float
) -> bool:
    """Whether a frame at `point` fits what the link drains before the next one (Salsify's
    rule): what still waits in the engine's queue plus this frame's share of the point's rate
    must leave at `rate_kbps` within `slack_frames` frame intervals of `fps`. A frame that
    does not fit is not coded (a skip), so nothing queues behind a burst; a codec that may
    not be skipped for backlog always fits."""
    if not spec(point.codec).skip_for_backlog:
        return True
    interval_s = 1.0 / fps
    frame_bits = point.rate_kbps * 1000.0 * interval_s
    return queued_bits + frame_bits <= rate_kbps * 1000.0 * interval_s * slack_frames


def padding_bits(
    config, estimator, point: OperatingPoint, interval_s: float, *, sent_bits: int, probe: bool
) -> float | None:
    """Bits of padding to send behind a unit of `sent_bits` covering `interval_s` at `point`
    (`config` an `EngineConfig`, `estimator` its `EstimatorState`, `probe` the model codec's
    section's); None when no padding is due, and at most 0 when the unit already fills the
    interval's share of the estimate."""
    limit_kbps = float("inf")
    if config.estimator.kind == "webrtc":
        pass
    elif (
        spec(point.codec).role is Role.MODEL
        and probe
        and config.policy != "oracle"
        and estimator.queue_delay_ms <= config.estimator.queue_low_ms
    ):
        limit_kbps = min(
            config.switching.to_h264_above_kbps / config.safety,
            config.safety * estimator.estimate_kbps,
        )
    else:
        return None
    return min(estimator.estimate_kbps, limit_kbps) * 1000.0 * interval_s - sent_bits


def held(
    config, point: OperatingPoint, now_s: float, inflight: InFlight, seen_kbps: float, *,
    queued_bits: int, paced: bool, source_fps: float,
) -> bool:  # fmt: skip
    """Hold a frame at `point`: too much in flight, or (frame sizing on, with the pacer) it
    would not drain in time."""
    out = backlogged(config, point, now_s, inflight, seen_kbps, queued_bits=queued_bits)
    fit = config.pacer.fit_frames
    if fit > 0 and paced and not out:
        out = not frame_fits(
            point, queued_bits=queued_bits, slack_frames=fit,
            rate_kbps=seen_kbps * config.pacer.rate_factor, fps=min(point.fps, source_fps),
        )  # fmt: skip
    return out
