"""The engine's pacer: its own queue in front of the downlink, drained at the estimate's rate.

Units: times in seconds, rates in kbit/s, sizes in bits.

Everything the engine sends would otherwise go straight into the bottleneck's drop-tail queue,
where nothing can be taken back. The pacer keeps it here instead (as WebRTC's pacer does): a
token bucket lets packets leave at the rate it is given, with `burst_ms` of that rate as the
burst allowance, and a frame still waiting when it could no longer be shown in time (its
capture time plus `deadline_ms`, less the queueing delay the receiver last reported) is
dropped here, with the frames that depend on it, so the link carries only what can still be
used; the engine then forces a keyframe. A unit whose first packet left is sent whole (a
half-sent unit would break the receiver's chain). A keyframe is not dropped for being late
(however slow the link, something must get through, or the estimate could never see it),
only when a newer keyframe is queued behind it (it is superseded), or while the pacer holds
(in an outage nothing is measured anyway, and a keyframe held through it would arrive seconds
late).

Three classes, served in order: `PRIORITY` (the model codec's parameters: a few kbit/s the
switch chose because nothing larger fits, never dropped; when one comes, waiting full-frame
units are dropped, since the receiver would discard them behind it), `VIDEO` (full-frame and
region units), `PADDING` (probing bits; discarded after `padding_wait_ms`). The payloads are
opaque: the world's packets, which get their sequence numbers only when they leave, so a
dropped packet is never counted lost by the receiver.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import Any

__all__ = ["Pacer", "PacedPacket", "PacerRelease", "PRIORITY", "VIDEO", "PADDING"]

PRIORITY, VIDEO, PADDING = 0, 1, 2


@dataclass(frozen=True)
class PacedPacket:
    """One packet waiting in the pacer: `payload` is the world's, `unit` the coded unit it
    belongs to (-1: padding), `frame` the source frame whose deadline it has."""

    payload: Any
    size_bits: int
    unit: int
    frame: int
    deadline_s: float
    keyframe: bool = False


@dataclass(frozen=True)
class PacerRelease:
    """What leaves now (in order), the frames dropped, whether a keyframe must follow, and
    when to ask again (inf: not before something new is queued)."""

    sent: tuple[PacedPacket, ...]
    dropped_frames: tuple[int, ...]
    needs_keyframe: bool
    next_s: float


class Pacer:
    """A token bucket over three queues; `push` and `release` are its only events."""

    def __init__(self, *, burst_ms: float, padding_wait_ms: float) -> None:
        self.burst_s = burst_ms / 1000.0
        self.padding_wait_s = padding_wait_ms / 1000.0
        self.queues: tuple[deque, deque, deque] = (deque(), deque(), deque())
        self.tokens_bits = 0.0
        self.last_s: float | None = None
        self.started_unit = -2  # the unit whose packets are leaving (-2: none)
        self.queued_bits = 0

    def push(self, packets: list[PacedPacket], priority: int) -> tuple[int, ...]:
        """Queue one unit's packets (or padding) in class `priority`; returns the frames of the
        full-frame units dropped because a priority unit overtakes them."""
        dropped: list[int] = []
        if priority == PRIORITY and packets:
            dropped = self._drop_video(lambda packet: packet.unit != self.started_unit)
        elif priority == VIDEO and packets and packets[0].keyframe:
            # A new keyframe supersedes every full-frame unit waiting before it.
            dropped = self._drop_video(lambda packet: packet.unit != self.started_unit)
        for packet in packets:
            self.queues[priority].append(packet)
            self.queued_bits += packet.size_bits
        return tuple(dropped)

    def release(
        self, now_s: float, rate_kbps: float, *, network_delay_s: float, hold: bool = False
    ) -> PacerRelease:
        """Send what the bucket allows at `now_s` at `rate_kbps` (inf: everything); drop what
        is too late. With
        `hold` (the feedback is silent: an outage or a handover gap) nothing leaves, the bucket
        does not fill, and deadlines are still judged at `rate_kbps`."""
        rate_bps = max(rate_kbps, 1e-3) * 1000.0
        burst_bits = rate_bps * self.burst_s
        if self.last_s is None or math.isinf(rate_bps):
            self.tokens_bits = burst_bits  # an idle pacer's bucket is full; unlimited: always
        elif hold:
            self.tokens_bits = min(self.tokens_bits, 0.0)
        else:
            self.tokens_bits = min(burst_bits, self.tokens_bits + (now_s - self.last_s) * rate_bps)
        self.last_s = now_s
        dropped: list[int] = []
        while late := self._drop_late(now_s, rate_bps, network_delay_s, keyframes=hold):
            dropped += late
        video = self.queues[VIDEO]
        needs_keyframe = bool(dropped) and not (video and video[0].keyframe)
        sent: list[PacedPacket] = []
        while self.tokens_bits > 0.0 and not hold:
            packet = self._next()
            if packet is None:
                break
            self.tokens_bits -= packet.size_bits
            self.queued_bits -= packet.size_bits
            sent.append(packet)
        next_s = float("inf")
        if any(self.queues) and not hold:
            next_s = now_s + max(1e-4, -self.tokens_bits / rate_bps + 1e-9)
        return PacerRelease(tuple(sent), tuple(dropped), needs_keyframe, next_s)

    def _next(self) -> PacedPacket | None:
        # A unit partly sent goes on first, whatever its class.
        for queue in self.queues:
            if queue and queue[0].unit == self.started_unit and queue[0].unit >= 0:
                return self._pop(queue)
        for queue in self.queues:
            if queue:
                return self._pop(queue)
        return None

    def _pop(self, queue: deque) -> PacedPacket:
        packet = queue.popleft()
        self.started_unit = packet.unit if queue and queue[0].unit == packet.unit else -2
        return packet

    def _drop_late(
        self, now_s: float, rate_bps: float, network_delay_s: float, *, keyframes: bool
    ) -> list[int]:
        padding = self.queues[PADDING]
        while padding and padding[0].deadline_s + self.padding_wait_s < now_s:
            self.queued_bits -= padding.popleft().size_bits
        video = self.queues[VIDEO]
        if not video:
            return []
        head = video[0]
        if head.unit == self.started_unit or (head.keyframe and not keyframes):
            return []
        unit_bits = sum(p.size_bits for p in video if p.unit == head.unit)
        ahead_bits = sum(p.size_bits for p in self.queues[PRIORITY])
        leaves_s = now_s + max(0.0, ahead_bits + unit_bits - self.tokens_bits) / rate_bps
        if leaves_s + network_delay_s <= head.deadline_s:
            return []
        # Too late: it and every unit that depends on it, up to the next keyframe.
        return self._drop_video(lambda packet: True, until_keyframe=True)

    def _drop_video(self, droppable, *, until_keyframe: bool = False) -> list[int]:
        video, kept, frames = self.queues[VIDEO], deque(), []
        first_unit = video[0].unit if video else None
        stop = False
        for packet in video:
            if until_keyframe and packet.keyframe and packet.unit != first_unit:
                stop = True
            if stop or not droppable(packet):
                kept.append(packet)
                continue
            self.queued_bits -= packet.size_bits
            if not frames or frames[-1] != packet.frame:
                frames.append(packet.frame)
        self.queues = (self.queues[PRIORITY], kept, self.queues[PADDING])
        return frames
