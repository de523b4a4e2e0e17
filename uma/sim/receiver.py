"""The mobile receiver: reassembles and really decodes frames, reports, and plays them out.

Units: simulation time in seconds; delays in ms in reports and logs; sizes in bits.

A unit (encoded frame) is decodable when all its packets arrived and the reference chain is
intact: it is a keyframe, or it directly follows the last decoded unit of the same codec. A
change of codec starts a new chain, which must begin with a keyframe (an IDR, or an intra
parameter set for MBC); `decode` dispatches on the unit's codec. A lost packet breaks the chain
until the next keyframe, and the receiver asks for one. Each source frame has a display deadline
(capture time + playout delay); at that instant the display shows the newest decoded frame not
newer than it. The display is frozen when that is not the frame the engine meant to be seen then
(the last frame the rung's frame rate scheduled): a late, lost, undecodable or backlog-skipped
frame freezes it; a lower frame rate by design does not.

Every arrival also goes to a `DeliveryTracker` (`uma.control`), whose report of the interval
(packet trains, loss, queueing-delay samples, the packets themselves) rides in each receiver
report for the engine's rate controller. On a change of the technology the receiver is on, the
tracker forgets the path's propagation delay, and once more `PATH_SETTLE_S` later, when the
packets the old path still carried have arrived.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from uma.control.delivery import DeliveryTracker
from uma.engine.reports import KeyframeRequest, ReceiverReport
from uma.metrics.framelog import FrameLog
from uma.sim.packets import EncodedUnit, Packet
from uma.sim.stats import RefreshReceived

__all__ = ["ReceiverState", "PATH_SETTLE_S"]

# After a technology change, the old path's packets still arrive for about this long.
PATH_SETTLE_S = 1.0


@dataclass
class ReceiverState:
    """Everything the receiver knows; packet and timer handlers are its methods."""

    log: FrameLog
    # The unit's pictures by frame (one for H.264, each frame of an MBC packet); {}: undecodable.
    decode: Callable[[EncodedUnit], dict[int, np.ndarray]]
    request_keyframe: Callable[[KeyframeRequest], None]
    now: Callable[[], float]
    # Tuning from `ReceiverConfig`: ask again for an IDR when none came this long after the last
    # request; one-way delays older than this no longer set the base (a handover changes it).
    keyframe_retry_s: float = 1.0
    base_delay_window_s: float = 10.0
    assembling: dict[int, list] = field(default_factory=dict)  # unit_seq -> [unit, packets got]
    expected_unit: int = 0
    broken: bool = False
    codec: str = ""  # the codec of the current reference chain ("": none yet)
    last_request_s: float = float("-inf")
    decoded: dict[int, np.ndarray] = field(default_factory=dict)  # frame -> picture
    # (frame, decode_s, told the playout) of every picture put in `decoded`, in order: what a
    # playout replay needs (`uma.sim.playout_replay`).
    decoded_log: list[tuple[int, float, bool]] = field(default_factory=list)
    # Report counters since the previous report.
    bits: int = 0
    packets: int = 0
    lost: int = 0
    highest_seq: int = -1
    owd_sum_s: float = 0.0
    base_window: deque = field(default_factory=deque)  # (time_s, owd_s), increasing owd
    # What arrived and when, for the rate controller (None: not reported).
    delivery: DeliveryTracker | None = None
    last_technology: str = ""
    settle_at_s: float | None = None  # when the new path's delay is measured afresh once more
    # Told (frame, arrival_s) of every decoded frame: the adaptive playout listens.
    on_decoded: Callable[[int, float], None] | None = None
    # The content description's chunks received, and when the last one came (cached: MBC
    # can be rendered from then on).
    description_chunks: set = field(default_factory=set)
    description_done_s: float | None = None
    # The access technology the receiver is on now (its reports carry it); None: not told.
    technology: Callable[[], str] | None = None
    # The model-aided refresh: decode a complete refresh unit (its picture, None when it cannot),
    # and the refresh the model codec renders from now (reports carry it). A refresh chain of
    # its own: an intra refresh, then each predicted from the one before.
    decode_refresh: Callable[[EncodedUnit], np.ndarray | None] | None = None
    refresh_frame: Callable[[], int] | None = None
    refresh_assembling: dict[int, list] = field(default_factory=dict)
    refresh_expected: int = 0
    refresh_broken: bool = True
    refresh_received: RefreshReceived = field(default_factory=RefreshReceived)

    def on_packet(self, packet: Packet) -> None:
        now_s = self.now()
        if packet.seq > self.highest_seq + 1:
            self.lost += packet.seq - self.highest_seq - 1
        self.highest_seq = max(self.highest_seq, packet.seq)
        self.bits += packet.size_bits
        self.packets += 1
        owd_s = now_s - packet.sent_s
        self.owd_sum_s += owd_s
        self._track_base(now_s, owd_s)
        if self.delivery is not None:
            self.delivery.on_packet(
                packet.seq, packet.sent_s * 1000.0, now_s * 1000.0, packet.size_bits
            )

        unit = packet.unit
        if unit is None:
            if packet.chunk >= 0:
                self._description_chunk(packet, now_s)
            return  # padding: counted and seen by the estimator, nothing to decode
        if unit.refresh:
            self._refresh_packet(packet, unit)
            return
        if unit.unit_seq < self.expected_unit:
            return  # a reordered packet of a unit the chain has passed: too late to use
        # The link is FIFO: a packet of a later unit means earlier incomplete units are lost.
        for seq in [s for s in self.assembling if s < unit.unit_seq]:
            del self.assembling[seq]
            self._chain_broken(seq)
        entry = self.assembling.setdefault(unit.unit_seq, [unit, 0])
        entry[1] += 1
        if entry[1] == packet.count:
            del self.assembling[unit.unit_seq]
            self._complete(unit, now_s)

    def _complete(self, unit: EncodedUnit, now_s: float) -> None:
        if not unit.keyframe and (
            self.broken or unit.unit_seq != self.expected_unit or unit.codec != self.codec
        ):
            self._chain_broken(unit.unit_seq)
            return
        pictures = self.decode(unit)
        if not pictures:
            self._chain_broken(unit.unit_seq)
            return
        self.broken = False
        self.codec = unit.codec
        self.expected_unit = unit.unit_seq + 1
        for frame, picture in pictures.items():
            self.decoded[frame] = picture
            self.log["arrival_ms"][frame] = now_s * 1000.0
            self.log["decoded"][frame] = 1
            self.decoded_log.append((frame, now_s, True))
            if self.on_decoded is not None:
                self.on_decoded(frame, now_s)

    def _refresh_packet(self, packet: Packet, unit: EncodedUnit) -> None:
        if unit.unit_seq < self.refresh_expected:
            return
        for seq in [s for s in self.refresh_assembling if s < unit.unit_seq]:
            del self.refresh_assembling[seq]  # FIFO: a later refresh's packet, this one is lost
            self.refresh_received.lost += 1
            self.refresh_broken = True
        entry = self.refresh_assembling.setdefault(unit.unit_seq, [unit, 0])
        entry[1] += 1
        if entry[1] < packet.count:
            return
        del self.refresh_assembling[unit.unit_seq]
        if not unit.keyframe and (self.refresh_broken or unit.unit_seq != self.refresh_expected):
            self._refresh_broken(unit)
            return
        picture = self.decode_refresh(unit) if self.decode_refresh is not None else None
        if picture is None:
            self._refresh_broken(unit)
            return
        self.refresh_broken = False
        self.refresh_expected = unit.unit_seq + 1
        self.refresh_received.decoded += 1
        if isinstance(picture, np.ndarray):
            # The best picture the receiver has of that instant, if it is still to be shown.
            self.decoded[unit.frame] = picture
            self.decoded_log.append((unit.frame, self.now(), False))

    def _refresh_broken(self, unit: EncodedUnit) -> None:
        """The refresh chain is broken (the last good reference stays): ask for an intra one."""
        self.refresh_broken = True
        self.refresh_expected = unit.unit_seq + 1
        now_s = self.now()
        self.request_keyframe(KeyframeRequest(sent_s=now_s, frame=unit.frame, refresh=True))

    def _description_chunk(self, packet: Packet, now_s: float) -> None:
        # The engine sends the description's chunks round and round until a report says it
        # is complete, so a lost chunk comes again.
        self.description_chunks.add(packet.chunk)
        if len(self.description_chunks) == packet.count and self.description_done_s is None:
            self.description_done_s = now_s

    def _chain_broken(self, unit_seq: int) -> None:
        if unit_seq < self.expected_unit and not self.broken:
            return  # a stale duplicate; the chain already moved on
        self.broken = True
        now_s = self.now()
        if now_s - self.last_request_s >= self.keyframe_retry_s or self.last_request_s < 0:
            self.last_request_s = now_s
            self.request_keyframe(KeyframeRequest(sent_s=now_s, frame=unit_seq))

    def _track_base(self, now_s: float, owd_s: float) -> None:
        window = self.base_window
        while window and window[-1][1] >= owd_s:
            window.pop()
        window.append((now_s, owd_s))
        while window[0][0] < now_s - self.base_delay_window_s:
            window.popleft()

    def make_report(self, interval_s: float) -> ReceiverReport:
        """Summarise the interval since the last report and reset its counters."""
        now_s = self.now()
        if self.broken and now_s - self.last_request_s >= self.keyframe_retry_s:
            self.last_request_s = now_s
            self.request_keyframe(KeyframeRequest(sent_s=now_s, frame=self.expected_unit))
        queue_ms = None
        if self.packets:
            base_s = self.base_window[0][1]
            queue_ms = max(0.0, (self.owd_sum_s / self.packets - base_s) * 1000.0)
        technology = self.technology() if self.technology is not None else ""
        delivery = self._delivery_report(now_s, technology)
        report = ReceiverReport(
            sent_s=now_s,
            interval_s=interval_s,
            received_bits=self.bits,
            packets_received=self.packets,
            packets_lost=self.lost,
            highest_seq=self.highest_seq,
            queue_delay_ms=queue_ms,
            description_complete=self.description_done_s is not None,
            technology=technology,
            refresh_frame=self.refresh_frame() if self.refresh_frame is not None else -1,
            delivery=delivery,
        )
        self.bits = self.packets = self.lost = 0
        self.owd_sum_s = 0.0
        return report

    def _delivery_report(self, now_s: float, technology: str):
        """The tracker's report of the interval; a new path's delay measured afresh."""
        if self.delivery is None:
            return None
        report = self.delivery.flush(now_s * 1000.0)
        if technology != self.last_technology:
            if self.last_technology:
                self.delivery.on_path_change()
                self.settle_at_s = now_s + PATH_SETTLE_S
            self.last_technology = technology
        elif self.settle_at_s is not None and now_s >= self.settle_at_s:
            self.delivery.on_path_change()
            self.settle_at_s = None
        return report
