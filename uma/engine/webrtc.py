"""WebRTC's receiver-side bandwidth estimator as a baseline for the engine's own.

Units: times in seconds, rates in kbit/s, sizes in bits.

The estimator is aiortc's port of webrtc.org's remote bitrate estimator
(`aiortc.rate.RemoteBitrateEstimator`: packets grouped by send time, a Kalman filter on the
growth of the inter-arrival delay, an over-use detector with an adaptive threshold, AIMD rate
control), used as the library ships it. The receiver feeds it every packet's arrival time, its
send time as the 24-bit abs-send-time header extension (6.18 fixed-point seconds, wrapping every
64 s) and its size; its latest estimate is the engine's at each receiver report, as a REMB (RTCP
receiver estimated maximum bitrate) would carry it. The engine runs it (`uma.engine.rate.
WebrtcRate`) over the packets each report lists, in arrival order: the estimate at each report
is the one a receiver running it would have sent.

One difference from webrtc.org is put back: libwebrtc's inter-arrival filter ends a burst
(packets arriving within 5 ms of each other, merged into one group) after 100 ms
(`kMaxBurstDurationMs`); aiortc 1.16's port lacks that bound, so once the bottleneck queues
packets back to back at more than about 2 Mbit/s (1240-byte packets 5 ms apart) every packet
joins the current group, no delay gradient is measured and the estimator is blind to the
queue it builds (`tests/engine/test_webrtc.py` shows it). `RembEstimator` swaps in a subclass
of aiortc's `InterArrival` with the bound (`max_burst=False` keeps aiortc's as it ships).

aiortc is imported only when a `RembEstimator` is made: it pulls in aiortc's whole WebRTC stack
(about a second).
"""

from __future__ import annotations

from uma.errors import ConfigError

__all__ = ["RembEstimator", "abs_send_time"]

# abs-send-time: seconds in 6.18 fixed point, 24 bits (RFC 8285 extension, webrtc.org's format).
_ABS_SEND_TIME_FRACTION_BITS = 18
_ABS_SEND_TIME_MASK = 0xFFFFFF
# One media stream; the estimator keys its REMB by SSRC.
_SSRC = 1
# libwebrtc's kMaxBurstDurationMs: a burst group ends this long after its first packet.
MAX_BURST_DURATION_MS = 100


def _bounded_inter_arrival(base):
    """aiortc's `InterArrival` with libwebrtc's maximum burst duration (a subclass of it)."""
    from aiortc.rate import BURST_DELTA_THRESHOLD_MS, InterArrival
    from aiortc.utils import uint32_add

    class BoundedInterArrival(InterArrival):
        first_arrival_ms: int | None = None

        def compute_deltas(self, timestamp: int, arrival_time: int, packet_size: int):
            group = self.current_group
            deltas = super().compute_deltas(timestamp, arrival_time, packet_size)
            if self.current_group is not group:
                self.first_arrival_ms = arrival_time
            return deltas

        def belongs_to_burst(self, timestamp: int, arrival_time: int) -> bool:
            group = self.current_group
            delta_ms = round(self.timestamp_to_ms * uint32_add(timestamp, -group.last_timestamp))
            if delta_ms == 0:
                return True
            arrival_delta_ms = arrival_time - group.arrival_time
            return (
                arrival_delta_ms - delta_ms < 0
                and arrival_delta_ms <= BURST_DELTA_THRESHOLD_MS
                and arrival_time - self.first_arrival_ms < MAX_BURST_DURATION_MS
            )

    return BoundedInterArrival(base.group_length, base.timestamp_to_ms)


def abs_send_time(sent_s: float) -> int:
    """The 24-bit abs-send-time of a packet sent at `sent_s`."""
    return int(round(sent_s * (1 << _ABS_SEND_TIME_FRACTION_BITS))) & _ABS_SEND_TIME_MASK


class RembEstimator:
    """aiortc's `RemoteBitrateEstimator` fed from simulated packets; `estimate_kbps` is its REMB.

    With `max_burst` (the default) its inter-arrival filter bounds bursts as libwebrtc does.

    `estimate_kbps` is None until the estimator first gives an estimate (it waits for 3 s of
    received-rate measurement, or an over-use). Packet sizes are the sizes on the wire (payload
    and headers), which is what the link serialises and so what the arrival times reflect.
    """

    def __init__(self, *, max_burst: bool = True) -> None:
        try:
            from aiortc.rate import RemoteBitrateEstimator
        except ImportError:
            raise ConfigError(
                "engine.estimator: 'webrtc' needs aiortc, got none installed "
                "(pip install 'uma[webrtc]')"
            ) from None

        self._estimator = RemoteBitrateEstimator()
        if max_burst:
            self._estimator.inter_arrival = _bounded_inter_arrival(self._estimator.inter_arrival)
        self.estimate_kbps: float | None = None
        self.updates = 0

    def on_packet(self, *, arrival_s: float, sent_s: float, size_bits: int) -> None:
        result = self._estimator.add(
            arrival_time_ms=int(round(arrival_s * 1000.0)),
            abs_send_time=abs_send_time(sent_s),
            payload_size=size_bits // 8,
            ssrc=_SSRC,
        )
        if result is not None:
            self.estimate_kbps = result[0] / 1000.0
            self.updates += 1
