"""The padding the engine sends behind a coded unit, so its bandwidth estimate can grow.

Units: rates in kbit/s, times in seconds, sizes in bits.

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
from uma.engine.estimator import EstimatorState
from uma.engine.points import OperatingPoint

__all__ = ["padding_bits"]


def padding_bits(
    config,
    estimator: EstimatorState,
    *,
    point: OperatingPoint,
    model_config,
    interval_s: float,
    sent_bits: int,
) -> float | None:
    """Bits of padding to follow a unit of `sent_bits` covering `interval_s` at `point`
    (`config` an `EngineConfig`); None when no padding is due, and at most 0 when the unit
    already fills the interval's share of the estimate."""
    limit_kbps = float("inf")
    if config.estimator.kind == "webrtc":
        pass
    elif (
        spec(point.codec).role is Role.MODEL
        and model_config.probe
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
