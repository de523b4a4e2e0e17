"""The model-aided refresh's decisions: when to code a refresh picture, whether intra, and
when its packets leave (docs/refresh.md).

Units: times in seconds, rates in kbit/s, sizes in bits.

While the engine is on the model codec, the budget (safety x estimate) leaves `spare` =
budget - the model point's rate, the budget never above the most the link delivered over
any of the estimator's windows in the last `max_interval_ms` (the estimate overshoots a slow
link while the model codec's probe pads: GSM's 9.6 kbit/s read as 20; what arrived does not;
over the last window alone, refreshes spaced beyond it would cap their own rate by a window
without them, each shrinking the next). A refresh is H.264 of the whole
picture; an intra one starts a stream sized to what `share` x spare carries in `interval_ms` (within
`min_frame_bits` and `max_frame_bits`), and the refreshes after it are predicted from the one
before at that size. The spare rate sets how often: the next is ordered once the last has
left and its bits at `share` x spare would have taken as long, never sooner than
`min_interval_ms` after it, and none while that would take longer than `max_interval_ms` or
less than `min_spare_kbps` are spare. Its packets wait here and leave at the spare rate, a
packet whenever the credit allows, so the parameters never queue behind a whole refresh;
nothing leaves while the rate control holds the refresh (the reports late or paused:
`RateControl.refresh_held`), nor while the last report's queueing delay is more than
`queue_high_ms` above the least of the last `queue_window_ms` (a handover to a slower technology raises the delay the
receiver reads for as long as it remembers the old link's, with no queue behind it), and
when the spare rate falls under way they still leave at half `min_spare_kbps` (a refresh
coded before the estimate fell, as it does while a handover's queue drains, still arrives,
and its bits let the estimate grow again). A refresh is intra at the start of a stretch,
after the receiver asked for one (a refresh lost or undecodable), and when the spare rate
has grown to twice the stream's size an interval; one left half sent when the engine leaves
the model codec is dropped, and the next is intra; so is one whose remaining bits would take
more than `handover_drain_ms` at the estimate when the reports name a new technology (they
would hold the parameters behind them on a slower link). The receiver reports the newest refresh
it renders from; the engine hands it on once (`take_adopted`), so the encoder's mirror of
the receiver's reference changes only when the receiver's did.

One Enum of states, one transition table, as `uma.engine.model` keeps the model codec's.
"""

from __future__ import annotations

import math
from collections import deque
from enum import Enum

from uma.engine.decisions import DiscardRefresh, RefreshCoded, RefreshOrder
from uma.engine.records import EngineEvent, Tally
from uma.engine.sending import cut

__all__ = ["RefreshState", "RefreshEvent", "REFRESH_TRANSITIONS", "RefreshOrder", "RefreshPlanner"]


class RefreshState(Enum):
    OFF = "off"  # not on the model codec (or refresh disabled)
    WAITING = "waiting"  # on the model codec, the next refresh not yet due
    SENDING = "sending"  # a refresh's packets are leaving


class RefreshEvent(Enum):
    ENTER = "enter"  # a frame on the model codec's point
    CODED = "coded"  # a refresh was coded and its packets queued here
    DRAINED = "drained"  # its last packet left
    LEAVE = "leave"  # a frame off the model codec's point


S, E = RefreshState, RefreshEvent
REFRESH_TRANSITIONS: dict[tuple[RefreshState, RefreshEvent], RefreshState] = {
    (S.OFF, E.ENTER): S.WAITING,
    (S.WAITING, E.ENTER): S.WAITING,
    (S.SENDING, E.ENTER): S.SENDING,
    (S.WAITING, E.CODED): S.SENDING,
    (S.SENDING, E.DRAINED): S.WAITING,
    **{(state, E.LEAVE): S.OFF for state in RefreshState},
}


class RefreshPlanner:
    """The refresh's state, its queue of packets (opaque to it) and the credit they leave on.

    `config` is an `engine.mbc.refresh` section (`uma.config.codecs.RefreshConfig`). Its
    transitions return the events and counts they cause (`refreshes`, `refresh_intra`,
    `refresh_dropped`, `refresh_adopted`, `refresh_skipped`).
    """

    COUNTS = ("refreshes", "refresh_intra", "refresh_dropped", "refresh_adopted", "refresh_skipped")

    def __init__(self, config) -> None:
        self.config = config
        self.state = RefreshState.OFF
        self.queue: deque[tuple[object, int]] = deque()
        self.delays: deque[tuple[float, float]] = deque()  # (now_s, queue_ms), increasing
        self.received: deque[tuple[float, float]] = deque()  # (now_s, kbit/s), decreasing
        self.credit_bits = 0.0
        self.spare_kbps = 0.0
        self.last_coded_s = -math.inf
        self.last_pace_s: float | None = None
        self.intra_due = True
        self.frame_bits = 0  # the size the refresh stream codes at (0: none yet)
        self.last_bits = 0.0  # the last refresh's size
        self.released_bits = 0  # since the last `take_released_bits`
        self.acked_frame = -1
        self.adopted: int | None = None  # a refresh the receiver took, not yet handed on

    def fire(self, event: RefreshEvent) -> None:
        key = (self.state, event)
        if key not in REFRESH_TRANSITIONS:
            raise RuntimeError(f"refresh: no transition from {self.state.name} on {event.name}")
        self.state = REFRESH_TRANSITIONS[key]

    @property
    def queued_bits(self) -> int:
        return sum(bits for _, bits in self.queue)

    def on_frame(
        self,
        frame: int,
        now_s: float,
        *,
        on_model: bool,
        budget_kbps: float,
        model_kbps: float,
        received_kbps: float = math.inf,
    ) -> tuple[RefreshOrder | None, list]:
        """The engine sends `frame` at `now_s`, on the model codec's point or not: a refresh
        to code with it (or None), and the actions leaving the model codec caused. The spare
        rate is the budget, never more than what the link delivered lately
        (`received_kbps`), less the model point's rate."""
        if not self.config.enabled:
            return None, []
        if not on_model:
            actions = []
            if self.state is not RefreshState.OFF:
                actions = self._drop(now_s, "left the model codec")
                self.fire(RefreshEvent.LEAVE)
                self.intra_due = True
            return None, actions
        return self._order(frame, now_s, budget_kbps, model_kbps, received_kbps), []

    def _order(
        self, frame: int, now_s: float, budget_kbps: float, model_kbps: float, received_kbps: float
    ) -> RefreshOrder | None:
        config = self.config
        self.fire(RefreshEvent.ENTER)
        delivered_kbps = self._delivered(now_s, received_kbps)
        self.spare_kbps = max(0.0, min(budget_kbps, delivered_kbps) - model_kbps)
        if self.spare_kbps < config.min_spare_kbps:
            return None
        if self.state is not RefreshState.WAITING:
            return None
        rate_bps = config.share * self.spare_kbps * 1000.0
        # What a refresh an interval would be now; a stream's refreshes keep its first size.
        wanted_bits = min(max(rate_bps * config.interval_ms / 1000.0, config.min_frame_bits),
                          config.max_frame_bits)  # fmt: skip
        if self.frame_bits and wanted_bits >= 2.0 * self.frame_bits:
            self.intra_due = True  # the link gives far more now: a larger stream, from intra
        # The last refresh's own bits at the share of the spare rate set the interval.
        bits = wanted_bits if self.intra_due else self.last_bits
        interval_s = bits / rate_bps
        if interval_s > config.max_interval_ms / 1000.0:
            return None
        interval_s = max(interval_s, config.min_interval_ms / 1000.0)
        if now_s - self.last_coded_s < interval_s - 1e-9:
            return None
        intra, self.intra_due = self.intra_due, False
        if intra:
            self.frame_bits = int(round(wanted_bits / 500.0)) * 500
        self.last_coded_s = now_s
        return RefreshOrder(frame, self.frame_bits / 1000.0, 1.0, intra)

    def _delivered(self, now_s: float, received_kbps: float) -> float:
        """The most the link delivered over any received window of the last
        `max_interval_ms`: a refresh spaced beyond one window would otherwise cap its own
        spare rate by a window without it, and each refresh's would shrink the next's."""
        memory = self.received
        while memory and memory[-1][1] <= received_kbps:
            memory.pop()
        memory.append((now_s, received_kbps))
        while memory[0][0] < now_s - self.config.max_interval_ms / 1000.0:
            memory.popleft()
        return memory[0][1]

    def coded(self, packets: list[tuple[object, int]], now_s: float, *, intra: bool) -> list:
        """The refresh ordered was coded as `packets` ((packet, size_bits) each; none: not
        sent): they wait for `pace`."""
        if self.state is not RefreshState.WAITING:
            return []
        if not packets:  # not sent (no pose, or no better than the receiver's picture)
            return [Tally("refresh_skipped")]
        self.queue.extend(packets)
        self.last_bits = float(sum(bits for _, bits in packets))
        kind = "intra" if intra else "predicted"
        detail = f"{kind} {self.last_bits:.0f} bits; spare {self.spare_kbps:.1f} kbps"
        self.credit_bits = 0.0
        self.last_pace_s = now_s
        self.fire(RefreshEvent.CODED)
        return [
            EngineEvent(now_s, "refresh", detail),
            Tally("refreshes"),
            Tally("refresh_intra", int(intra)),
        ]

    def on_coded(self, coded: RefreshCoded | None, now_s: float) -> list:
        """The refresh ordered, coded (None: it could not be, the model codec had no pose for
        it): sent when it beats what the receiver renders by `min_gain_db`, else discarded."""
        if coded is None:
            return self.coded([], now_s, intra=False)
        if coded.gain_db is not None and coded.gain_db < self.config.min_gain_db:
            return [DiscardRefresh(coded.frame), *self.coded([], now_s, intra=False)]
        packets = cut("refresh", coded.payload, coded.size_bytes,
                      payload_bytes=self.config.packet_bytes)  # fmt: skip
        return self.coded(
            [(packet, packet.size_bits) for packet in packets], now_s, intra=coded.intra
        )

    def pace(
        self, now_s: float, *, queue_delay_ms: float, held: bool = False
    ) -> list[tuple[object, int]]:
        """The refresh packets ((packet, size_bits) each) that leave at `now_s`: the credit the
        spare rate gave since the last call allows them (one may overdraw it), none while the
        queue is building or while `held` (no credit accrues then; call it every frame: it
        keeps the recent delays)."""
        window_s = self.config.queue_window_ms / 1000.0
        delays = self.delays
        while delays and delays[0][0] < now_s - window_s:
            delays.popleft()
        while delays and delays[-1][1] >= queue_delay_ms:
            delays.pop()  # a later, lower delay is the window's least from now on
        delays.append((now_s, queue_delay_ms))
        if self.state is not RefreshState.SENDING:
            return []
        elapsed_s = max(0.0, now_s - (self.last_pace_s if self.last_pace_s is not None else now_s))
        self.last_pace_s = now_s
        if held or queue_delay_ms - delays[0][1] > self.config.queue_high_ms:
            return []
        rate_kbps = max(self.spare_kbps, 0.5 * self.config.min_spare_kbps)
        self.credit_bits += rate_kbps * 1000.0 * elapsed_s
        # The credit never stores more than one packet's worth: no burst after a pause.
        self.credit_bits = min(self.credit_bits, 8.0 * self.config.packet_bytes + 320.0)
        out = []
        while self.queue and self.credit_bits >= 0.0:
            packet, bits = self.queue.popleft()
            self.credit_bits -= bits
            self.released_bits += bits
            out.append((packet, bits))
        if not self.queue:
            self.fire(RefreshEvent.DRAINED)
        return out

    def on_handover(self, now_s: float, estimate_kbps: float) -> list:
        """The reports name a new technology: a refresh under way whose remaining bits would
        take more than `handover_drain_ms` at `estimate_kbps` (the new link's first estimate)
        is dropped, and the next is intra (its bits would hold the parameters behind them on
        a slower link)."""
        if self.queued_bits <= estimate_kbps * self.config.handover_drain_ms:
            return []
        return self._drop(now_s, f"handover, {estimate_kbps:.1f} kbps")

    def take_released_bits(self) -> int:
        """Refresh bits released since the last call (the probe's padding leaves them out)."""
        bits, self.released_bits = self.released_bits, 0
        return bits

    def request_intra(self, now_s: float) -> list:
        """The receiver lost a refresh (or could not decode it): the next one is intra."""
        self.intra_due = True
        return []

    def on_report(self, report, now_s: float, estimate_kbps: float, handover: bool) -> list:
        """A `ReceiverReport`: the refresh the receiver renders from (`on_ack`), and, when it
        named a new technology (`handover`: `RateControl.handover`, after the rate
        control took the report and the new technology's prior), `on_handover` at
        `estimate_kbps`."""
        actions = self.on_ack(report.refresh_frame)
        return actions + self.on_handover(now_s, estimate_kbps) if handover else actions

    def on_ack(self, frame: int) -> list:
        """A report says the receiver renders from the refresh of `frame`."""
        if frame <= self.acked_frame:
            return []
        self.acked_frame = frame
        self.adopted = frame
        return [Tally("refresh_adopted")]

    def take_adopted(self) -> int | None:
        """The refresh the receiver took since the last call (None: none)."""
        frame, self.adopted = self.adopted, None
        return frame

    def _drop(self, now_s: float, why: str) -> list:
        if not self.queue:
            return []
        detail = f"{len(self.queue)} packets; {why}"
        self.queue.clear()
        self.intra_due = True
        return [Tally("refresh_dropped"), EngineEvent(now_s, "refresh_dropped", detail)]
