"""The GCC baseline: delivery reports in, `RateDecision`s out.

Units: kbit/s, ms. Each `DeliveryReport`'s packets go through GCC's inter-arrival groups, the
trendline and the over-use detector (`uma.control.gcc_delay`); the last signal, the report's
received rate and its loss drive the AIMD and loss controllers (`uma.control.gcc_rate`); the
target is the smaller of the two. Probing: two clusters at start (3x and 6x the initial rate),
then one at 2x the target every `alr_probe_ms` while the stream is application-limited
(received below `alr_fraction` of the target); the next report's train rate, capped at the
probe's own rate, is the probe's result and raises the target when it is higher.
"""

from __future__ import annotations

from uma.control.actions import ProbeRequest, RateDecision
from uma.control.delivery import DeliveryReport
from uma.control.gcc_delay import InterArrival, OveruseDetector, Trendline, Usage
from uma.control.gcc_rate import AimdController, GccRateSettings, LossController

__all__ = ["GccController"]

PROBE_PACKETS = 5


class GccController:
    """Google Congestion Control as the draft and libwebrtc describe it."""

    def __init__(
        self,
        settings: GccRateSettings | None = None,
        *,
        rtt_ms: float = 100.0,
        alr_fraction: float = 0.65,
        alr_probe_ms: float = 5000.0,
    ) -> None:
        self.settings = settings or GccRateSettings()
        self.rtt_ms = rtt_ms
        self.alr_fraction, self.alr_probe_ms = alr_fraction, alr_probe_ms
        self.groups = InterArrival()
        self.trendline = Trendline()
        self.detector = OveruseDetector()
        self.aimd = AimdController(self.settings)
        self.loss = LossController(self.settings)
        self.usage = Usage.NORMAL
        self._start_probes = [3.0, 6.0]
        self._probe_kbps: float | None = None
        self._last_probe_ms = float("-inf")

    @property
    def target_kbps(self) -> float:
        return min(self.aimd.target_kbps, self.loss.bound_kbps)

    def on_report(self, report: DeliveryReport) -> RateDecision:
        """One feedback report: the new target, and a probe when one is due."""
        now_ms = report.end_ms
        for record in report.records:
            delta = self.groups.on_packet(record.send_ms, record.arrival_ms)
            if delta is not None:
                trend = self.trendline.update(delta)
                self.usage = self.detector.detect(trend, delta.send_delta_ms, delta.arrival_ms)
        reason = self.usage.value
        if self._probe_kbps is not None and report.capacity_kbps is not None:
            shown = min(report.capacity_kbps, self._probe_kbps)  # a probe shows at most its rate
            if shown > self.aimd.target_kbps:
                self.aimd.raise_to(shown)
                reason = "probe"
            self._probe_kbps = None
        received = report.received_kbps
        if report.packets:
            delay_based = self.aimd.update(self.usage, received, now_ms, self.rtt_ms)
            self.loss.update(report.loss_fraction, now_ms, delay_based)
        return RateDecision(self.target_kbps, self._probe(received, now_ms), reason)

    def _probe(self, received_kbps: float, now_ms: float) -> ProbeRequest | None:
        target = self.target_kbps
        if self._start_probes:
            rate = self._start_probes.pop(0) * self.settings.initial_kbps
        elif received_kbps < self.alr_fraction * target and (
            now_ms - self._last_probe_ms >= self.alr_probe_ms
        ):
            rate = 2.0 * target
        else:
            return None
        self._probe_kbps = rate
        self._last_probe_ms = now_ms
        return ProbeRequest(rate, PROBE_PACKETS, self.settings.packet_bits)
