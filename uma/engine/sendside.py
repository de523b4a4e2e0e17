"""What leaves the engine for the downlink once a frame is coded, and when the pacer lets go.

Units: times in seconds, rates in kbit/s, sizes in bits.

A coded unit goes into the outbox (`uma.engine.sending`: the pacer, the numbering) with the
padding due behind it when the rate control pads (`uma.engine.pacing.padding_bits`; refresh
bits released since the last unit fill that share too); a rate controller's probe leaves at
once, back to back (`Outbox.probe`); the refresh's packets leave at its planner's pace
(`uma.engine.refresh`); the pacer releases at `engine.pacer.rate_factor` x the rate it is
given, never slower than the point in use sends.
"""

from __future__ import annotations

from uma.codecs import Role, spec
from uma.engine.decisions import OutgoingUnit, PaceDecision, SendPacket
from uma.engine.pacing import padding_bits
from uma.engine.records import Tally
from uma.engine.refresh import RefreshPlanner
from uma.engine.sending import Outbox, dropped_actions

__all__ = ["SendSide"]


class SendSide:
    """The engine's sending: the outbox, and the refresh's packets (`refresh` None: off)."""

    def __init__(
        self, config, points, *, outbox: Outbox, refresh: RefreshPlanner | None,
        source_fps: float, pads: bool,
    ) -> None:  # fmt: skip
        self.config, self.points, self.outbox, self.refresh = config, points, outbox, refresh
        self.source_fps, self.pads = source_fps, pads

    def unit(self, unit: OutgoingUnit, now_s: float, estimator) -> list:
        """Queue a coded unit and the padding due behind it: what leaves at once, and why
        queued units were dropped."""
        point = self.points[unit.rung]
        actions, bits = self.outbox.unit(
            unit.payload, unit.size_bytes, frames=unit.frames, keyframe=unit.keyframe,
            priority=spec(point.codec).role is Role.MODEL, now_s=now_s,
        )  # fmt: skip
        interval_s = len(unit.frames) / min(point.fps, self.source_fps)
        bits += self.refresh.take_released_bits() if self.refresh is not None else 0
        if not self.pads:
            return actions
        pad = padding_bits(estimator.estimate_kbps, interval_s, sent_bits=bits)
        return actions + self.outbox.padding(pad, now_s)

    def probe(self, probe, now_s: float) -> list:
        """A rate controller's `ProbeRequest` (None: none): its packets, sent now, counted."""
        if probe is None:
            return []
        return self.outbox.probe(probe.packets, probe.packet_bits, now_s) + [Tally("probes", 1)]

    def refresh_due(self, now_s: float, rate) -> list[SendPacket]:
        """The refresh's packets that leave now, none while the rate control holds the
        refresh (`RateControl.refresh_held`; ask every frame: it keeps the recent delays)."""
        if self.refresh is None:
            return []
        out = self.refresh.pace(
            now_s, queue_delay_ms=rate.state.queue_delay_ms, held=rate.refresh_held(now_s)
        )
        return self.outbox.number([packet for packet, _ in out], now_s) if out else []

    def pace(
        self, now_s: float, *, seen_kbps: float, rung: int, queue_delay_ms: float
    ) -> tuple[PaceDecision, list, bool]:
        """What the pacer lets out at `now_s` at `seen_kbps` x `rate_factor`, the actions of
        what it dropped (late, given `queue_delay_ms` at the bottleneck), and whether a
        keyframe must follow."""
        if not self.outbox.paced:
            return PaceDecision((), float("inf")), [], False
        pacer = self.config.pacer
        # Never slower than the point in use sends (else nothing would be measured).
        rate_kbps = max(seen_kbps * pacer.rate_factor, self.points[rung].rate_kbps)
        sent, release = self.outbox.release(
            now_s, rate_kbps, network_delay_s=queue_delay_ms / 1000.0, hold=False
        )
        actions = dropped_actions(release.dropped_frames, now_s, "too late to be shown")
        return PaceDecision(tuple(sent), release.next_s), actions, release.needs_keyframe
