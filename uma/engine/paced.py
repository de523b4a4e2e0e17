"""The engine's pacer and handover calls, apart from the dispatcher: what `UmaEngine`'s
`on_unit_queued`, `on_padding_queued`, `on_pace` and a report's technology change do.

Units: times in seconds, rates in kbit/s, sizes in bits. Each function takes the engine and
changes only its pacer, estimate, keyframe request, counts and events.
"""

from __future__ import annotations

from uma.codecs import Role, spec
from uma.engine import refreshing
from uma.engine.decisions import PaceDecision, UnitSent
from uma.engine.handover import Handover, handover_estimate
from uma.engine.pacer import PADDING, PRIORITY, VIDEO, PacedPacket, Pacer
from uma.engine.pacing import padding_bits

__all__ = ["build", "unit_queued", "padding_queued", "pace", "take_handover_prior"]


def build(config, technology_priors_kbps) -> tuple[Pacer | None, Handover | None]:
    """The pacer and the handover rule a configuration asks for (None: off)."""
    pacer = config.pacer
    return (
        Pacer(burst_ms=pacer.burst_ms, padding_wait_ms=pacer.padding_wait_ms)
        if pacer.enabled
        else None,
        Handover(technology_priors_kbps or {}) if config.handover.enabled else None,
    )


def unit_queued(
    self, packets: list[tuple[object, int]], *, rung: int, frames: tuple[int, ...],
    keyframe: bool, now_s: float,
) -> UnitSent:  # fmt: skip
    """With the pacer on: a coded unit of point `rung` carrying `frames`, as the world's
    packets and their sizes, waits in the engine's queue (`on_pace` lets it out, numbered
    then). Its `first_seq` is -1; the padding due is queued with `on_padding_queued`."""
    assert self.pacer is not None, "on_unit_queued needs engine.pacer.enabled"
    unit, self.next_unit = self.next_unit, self.next_unit + 1
    point = self.points[rung]
    deadline_s = frames[-1] / self.ladder.source_fps + self.config.pacer.deadline_ms / 1000.0
    paced = [
        PacedPacket(payload, size, unit, frames[-1], deadline_s, keyframe)
        for payload, size in packets
    ]
    model = spec(point.codec).role is Role.MODEL
    dropped = self.pacer.push(paced, PRIORITY if model else VIDEO)
    _dropped(self, dropped, now_s, "model codec first")
    interval_s = len(frames) / min(point.fps, self.ladder.source_fps)
    sent_bits = sum(size for _, size in packets)
    sent_bits += refreshing.released_bits(self)  # refresh bits fill the probe's share too
    return UnitSent(-1, padding_bits(self, point, interval_s, sent_bits=sent_bits))


def padding_queued(self, packets: list[tuple[object, int]], now_s: float) -> None:
    """Padding packets wait in the pacer's lowest class."""
    assert self.pacer is not None, "on_padding_queued needs engine.pacer.enabled"
    paced = [PacedPacket(payload, size, -1, -1, now_s) for payload, size in packets]
    self.pacer.push(paced, PADDING)


def pace(self, now_s: float, *, capacity_kbps: float | None = None) -> PaceDecision:
    """The packets the pacer lets out at `now_s` (each numbered), and when to ask again;
    the oracle paces at the true capacity `capacity_kbps`."""
    assert self.pacer is not None, "on_pace needs engine.pacer.enabled"
    seen_kbps = self.estimate_kbps if capacity_kbps is None else capacity_kbps
    hold_s = self.config.pacer.hold_after_ms / 1000.0
    # Never slower than the point in use sends: a lowest rung above the estimate would
    # otherwise only queue here until its frames are dropped, and nothing be measured.
    rate_kbps = max(seen_kbps * self.config.pacer.rate_factor, self.points[self.rung].rate_kbps)
    release = self.pacer.release(
        now_s,
        rate_kbps,
        network_delay_s=self.estimator.queue_delay_ms / 1000.0,
        hold=hold_s > 0 and now_s - self.inflight.last_report_s > hold_s,
    )
    _dropped(self, release.dropped_frames, now_s, "too late to be shown")
    if release.needs_keyframe:
        self.keyframes.request()
    sizes = [packet.size_bits for packet in release.sent]
    first_seq = self.inflight.on_sent(sizes)
    sent = tuple((packet.payload, first_seq + i) for i, packet in enumerate(release.sent))
    return PaceDecision(sent, release.next_s)


def _dropped(self, frames: tuple[int, ...], now_s: float, why: str) -> None:
    if frames:
        self.counts["pacer_dropped_frames"] = self.counts.get("pacer_dropped_frames", 0) + len(
            frames
        )
        self._emit(now_s, "pacer_drop", f"frames {frames[0]}-{frames[-1]}: {why}")


def take_handover_prior(self, technology: str, now_s: float) -> None:
    """On a change of the reported access technology, the estimate takes its prior capacity."""
    prior_kbps = self.handover.on_report(technology)
    if prior_kbps is None:
        return
    config = self.config.estimator
    self.estimator = handover_estimate(
        self.estimator, prior_kbps, now_s=now_s, min_kbps=config.min_kbps,
        max_kbps=config.max_kbps,
    )  # fmt: skip
    self._emit(now_s, "handover_prior", f"{technology} {prior_kbps:.1f} kbps")
