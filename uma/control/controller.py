"""uma's rate controller: capacity from delivery, a drained queue, a trend check, a loss bound.

Units: kbit/s, ms, fractions. Events in, decisions out: `on_report(DeliveryReport)` after each
feedback report, `on_silence(now_ms)` when the feedback has gone quiet, `on_handover(technology,
now_ms)` when the link changes technology; each returns a `RateDecision`. One set of defaults
(`UmaSettings`) for every link:

- **capacity** is the link's delivery rate measured by packet trains (`DeliveryReport.
  capacity_kbps`), smoothed with a time constant over the trains' own measured time, so a
  clump of deliveries reads as the link's rate rather than as a queue; the report after a
  probe weighs at least `probe_weight` (a probe's few packets measure little time);
  with `take_queued_drop` (off by default) a train below the estimate is taken whole when the
  report's queueing delay rose past `queue_target_ms` (the stream filled the link: a drop);
  with `bounded_queued_drop` (off by default) such a train is taken whole once the newest
  sample is past `queue_low_ms`, but one report cuts the estimate at most to
  `queued_drop_floor` (a half) of itself;
- **queue**: the smallest queueing-delay sample of a report (bursty delivery jitters the
  others; a standing queue raises every one); above `queue_target_ms` the excess is drained
  over `drain_ms`; with `queue_from_owed` the queue is at most the bits the sender still has
  in flight at the capacity estimate (an outage's backlog behind a paused sender is gone);
- **trend**: GCC's trendline and adaptive threshold over the same packets; an over-use signal
  while the queue is above `queue_low_ms` backs the target off by `beta`;
- **loss**: GCC's loss-based bound (above 10 % down by half the loss, below 2 % free);
- **probing**: when no train measured the link for `probe_interval_ms` while the stream is
  application-limited (received below `alr_fraction` of the target) or the queue is short (a
  low target fills its own small frames, which make no trains), a probe of padding packets
  sent back to back, whose spacing measures the link, sized to queue about `probe_ms`;
  with `no_probe_while_owed` (off by default) none after a report that counted a packet due
  before its end and not in it (an outage read as application-limited: a probe sent into it
  only waits behind what is stuck); with `no_probe_into_silence` (off by default) none once
  the quiet clock has run `silence_ms` (the silence cut is due: an outage, not an idle sender);
  with `no_probe_while_paused` (on by default) none while the sender is `paused` (what is out
  is owed: a probe would only queue behind it);
- **pause**: no report for `pause_ms` (1.5 report intervals): `paused` says the sender should
  code nothing new until one comes (the skip rule's caller asks), so a handover's gap or an
  outage gets little of the stream, and a lost report costs a frame or two, not a rate. A
  report that holds no packet while the oldest one outstanding (`due`, the sender's own
  knowledge) should have arrived is no news from the link: the quiet clock runs from when
  that packet was due, and at `overdue_ms` (or the packet's own time at the capacity
  estimate, if longer) past it the sender pauses at once (a downlink outage with a live
  uplink: the receiver's reports keep coming, empty); with `overdue_in_any_report` (off by
  default) a report with packets counts the same way when the packet after its last one is
  overdue (the link stalled mid-report); with `fixed_due_time` (on by default) a packet's
  time at the estimate is taken when it is first found due, so a silence cut of the estimate
  does not move its due time later and end the pause while it is still out;
- **silence**: no report for `silence_ms` (an outage, a handover's gap) cuts the capacity to
  `silence_factor` of itself or of what arrived over the last `received_tau_ms`, whichever is
  less (an application-limited stream sends no more than that), once per `silence_ms`; when
  the first report with packets after it shows they met no queue and none was lost, the
  silence was a lost report and the cut is undone (never after a handover: a new path's first
  packets define its base delay, so meet none); with `judge_silence` (off by default) also
  when, on the same path and soon after, the packets held up by it came out as a train at the
  estimate before the cut or faster (an on/off link's off-period: `uma.control.silence`);
- **recovery** (`recover_after_silence`, off by default): a cut of an application-limited
  stream (received below `alr_fraction` of the capacity) is followed, at the first report
  within `recover_window_ms` whose packets met less than `queue_target_ms` of queue and no
  loss, by a probe sized for `recover_fraction` of the estimate before the cut (at most the
  prior of a technology named anew), and the next train measurement, if its report shows no
  backlog either, is taken whole up to that rate (GCC's probe after a large drop) rather than
  weighed by the little time a thin stream's trains measure;
- **handover**: the new technology's prior (`priors_kbps`) can only lower the capacity estimate,
  so a trace with no labelled handovers never sees it and a wrong prior costs one
  measurement's time, never a standing queue;
- **target** = capacity x `headroom` minus the drain, clamped to [min_kbps, max_kbps].
"""

from __future__ import annotations

import math

from uma.control.actions import ProbeRequest, RateDecision
from uma.control.delivery import DeliveryReport
from uma.control.gcc_delay import InterArrival, OveruseDetector, Trendline, Usage
from uma.control.gcc_rate import GccRateSettings, LossController
from uma.control.settings import DEFAULT_PRIORS_KBPS, UmaSettings
from uma.control.silence import SilenceJudge

__all__ = ["UmaSettings", "UmaController", "DEFAULT_PRIORS_KBPS"]


class UmaController:
    """The controller the engine is to follow (wired in through the engine's actions)."""

    def __init__(self, settings: UmaSettings | None = None) -> None:
        self.settings = s = settings or UmaSettings()
        self.capacity_kbps = s.initial_kbps
        self.target_kbps = s.initial_kbps * s.headroom
        self.queue_ms = 0.0
        self.loss = LossController(
            GccRateSettings(initial_kbps=s.initial_kbps, min_kbps=s.min_kbps, max_kbps=s.max_kbps)
        )
        self._reset_trend()
        self._last_train_ms = float("-inf")
        self._last_probe_ms = float("-inf")
        self._quiet_since_ms: float | None = None  # the last report's end
        self._silences = 0  # the cuts since it (`on_silence`)
        self._probe_pending = False
        self.received_kbps: float | None = None  # what arrived, smoothed over `received_tau_ms`
        self._judge = SilenceJudge()  # the capacity a silence cut from, until judged
        self._base_ms: float | None = None  # the path's one-way delay with no queue
        self._last_arrival_ms = float("-inf")
        self._overdue = False  # the last report was empty with a packet overdue
        self._owed = False  # the last report counted a packet due before its end, not in it
        self._recover_kbps: float | None = None  # a cut's capacity before it, to probe for
        self._recovering_kbps: float | None = None  # a recovery probe's rate, out
        self._recover_until_ms = float("-inf")  # no recovery probe after this
        self._due: tuple[float, int] | None = None  # the due packet `_service_ms` timed
        self._due_service_ms = 0.0

    def _reset_trend(self) -> None:
        self.groups = InterArrival()
        self.trendline = Trendline()
        self.detector = OveruseDetector()
        self.usage = Usage.NORMAL

    def on_report(
        self,
        report: DeliveryReport,
        *,
        due: tuple[float, int] | None = None,
        owed_bits: int | None = None,
        technology: str = "",
    ) -> RateDecision:
        """One feedback report in; the target (and a probe when the link is unmeasured) out.
        `due`: (send stamp in ms, size in bits) of the oldest packet sent and not yet in any
        report (the sender knows it): a report with no packet while that one was due is
        no news from the link (`_quiet_from`). `owed_bits`: the bits sent after the last
        packet reported (None: not known); with `queue_from_owed` the queue is at most their
        time at the capacity estimate (`_queue`). `technology`: one the report names anew (its
        prior caps a recovery probe; `on_handover` follows)."""
        s = self.settings
        now_ms = report.end_ms
        self._quiet_from(report, due)
        self._received(report)
        restored_kbps = self._judge.verdict(report, s, handover=bool(technology))
        if restored_kbps is not None:
            self.capacity_kbps = max(self.capacity_kbps, restored_kbps)
        if report.capacity_kbps is not None:
            weight = 1.0 - math.exp(-report.train_ms / s.capacity_tau_ms)
            if self._probe_pending:
                weight = max(weight, s.probe_weight)
            if s.take_queued_drop and self._queued_drop(report):
                weight = 1.0
            self.capacity_kbps = self._weighed(report, report.capacity_kbps, weight)
            self._recovered(report)
            self._last_train_ms = now_ms
            self._probe_pending = False
        self._queue(report, owed_bits)
        for record in report.records:
            delta = self.groups.on_packet(record.send_ms, record.arrival_ms)
            if delta is not None:
                trend = self.trendline.update(delta)
                self.usage = self.detector.detect(trend, delta.send_delta_ms, delta.arrival_ms)
        target, reason = self._target()
        if report.packets:
            target = min(target, self.loss.update(report.loss_fraction, now_ms, target))
            if target < self.loss.bound_kbps * 1.0001 and report.loss_fraction > 0.1:
                reason = "loss"
        self.target_kbps = self._bounded(target)
        probe = self._recovery_probe(report, technology, now_ms)
        return RateDecision(self.target_kbps, probe or self._probe(report, now_ms), reason)

    def _queue(self, report: DeliveryReport, owed_bits: int | None) -> None:
        """The queue a packet sent now meets: the report's smallest queueing-delay sample
        (bursty delivery jitters the others); with `queue_from_owed`, at most what the link
        still owes at the estimate, since in this path the queue is the stream's own: after
        an outage the report's packets waited it out, but a paused sender has little behind
        them, so that wait is a backlog gone, not a standing queue to drain."""
        if report.queue_delay_ms:
            self.queue_ms = min(report.queue_delay_ms)
        if self.settings.queue_from_owed and owed_bits is not None:
            self.queue_ms = min(self.queue_ms, owed_bits / self.capacity_kbps)

    def _weighed(self, report: DeliveryReport, train_kbps: float, weight: float) -> float:
        """The estimate moved `weight` of the way to the train; with `bounded_queued_drop`, a
        train below the estimate in a queue that built within the report (`_building`) is
        taken whole, but one report cuts the estimate to no less than `queued_drop_floor` of
        itself (a multiplicative decrease: a lasting drop halves it again next report)."""
        s = self.settings
        moved_kbps = self.capacity_kbps + weight * (train_kbps - self.capacity_kbps)
        if not (s.bounded_queued_drop and train_kbps < self.capacity_kbps):
            return moved_kbps
        if not self._building(report, s.queue_low_ms):
            return moved_kbps
        return min(moved_kbps, max(train_kbps, s.queued_drop_floor * self.capacity_kbps))

    @staticmethod
    def _building(report: DeliveryReport, above_ms: float) -> bool:
        """The report's newest queueing-delay sample is above `above_ms` and above its first:
        the stream filled the link within the report."""
        queue_ms = report.queue_delay_ms
        return bool(queue_ms) and queue_ms[-1] > max(above_ms, queue_ms[0])

    def _queued_drop(self, report: DeliveryReport) -> bool:
        """The report's train measured less than the estimate while its queueing delay rose
        past `queue_target_ms` (its newest sample above the target and above its first): the
        stream filled the link, so the train read the link's rate, not the sender's."""
        if report.capacity_kbps is None or report.capacity_kbps >= self.capacity_kbps:
            return False
        return self._building(report, self.settings.queue_target_ms)

    def _clear(self, report: DeliveryReport) -> bool:
        """The report's packets met less than `queue_target_ms` of queue and none was lost:
        the link delivers again with no backlog."""
        queue_ms = report.queue_delay_ms
        return bool(queue_ms) and min(queue_ms) < self.settings.queue_target_ms and not report.lost

    def _recovered(self, report: DeliveryReport) -> None:
        """A train measurement while a recovery probe is out: taken whole, up to the probe's
        rate (never lowering what the usual weighing gave), if the report shows no backlog
        and no loss (else the usual weighing alone)."""
        if self._recovering_kbps is not None and report.capacity_kbps is not None:
            if self._clear(report):
                taken_kbps = min(report.capacity_kbps, self._recovering_kbps)
                self.capacity_kbps = max(self.capacity_kbps, taken_kbps)
            self._recovering_kbps = None

    def _recovery_probe(
        self, report: DeliveryReport, technology: str, now_ms: float
    ) -> ProbeRequest | None:
        """After a silence cut, the first report whose packets met no backlog and no loss
        (the link delivers again, drained): a probe sized for the estimate before the cut,
        capped by the prior of a technology named anew since; none if the estimate is back
        there already."""
        if self._recover_kbps is None:
            return None
        if report.end_ms > self._recover_until_ms:
            self._recover_kbps = None  # too long after the cut: the link may have changed
            return None
        prior = self.settings.priors_kbps.get(technology) if technology else None
        if prior is not None:
            self._recover_kbps = min(self._recover_kbps, prior)
        if not self._clear(report):
            return None  # wait for a report with no backlog (none: `on_silence` cuts again)
        rate_kbps, self._recover_kbps = self._recover_kbps, None
        if rate_kbps <= self.capacity_kbps:
            return None
        self._recovering_kbps = rate_kbps
        self._last_probe_ms = now_ms
        self._probe_pending = True
        return self._sized_probe(rate_kbps)

    def _quiet_from(self, report: DeliveryReport, due: tuple[float, int] | None) -> None:
        """Move the quiet clock: to the report's end, unless the report holds no packet while
        the oldest outstanding one should have arrived (its send stamp plus the path's base
        delay, or the last arrival, plus its time at the capacity estimate): then the link
        has been quiet since that packet was due, as if the report had not come. With
        `overdue_in_any_report` a report with packets counts so too: the link stalled after
        its last arrival."""
        if report.records:
            last = report.records[-1]
            self._base_ms = last.arrival_ms - last.send_ms - report.queue_delay_ms[-1]
            self._last_arrival_ms = last.arrival_ms
        s = self.settings
        since_ms, grace_ms = report.end_ms, s.overdue_ms
        counts = s.overdue_in_any_report or not report.records
        if counts and due is not None and self._base_ms is not None:
            send_ms, size_bits = due
            start_ms = max(send_ms + self._base_ms, self._last_arrival_ms)
            service_ms = self._service_ms(due)
            since_ms = min(since_ms, start_ms + service_ms)
            grace_ms = max(grace_ms, service_ms)
        self._overdue = report.end_ms - since_ms >= grace_ms
        self._owed = since_ms < report.end_ms
        if self._quiet_since_ms is None or since_ms > self._quiet_since_ms:
            self._quiet_since_ms, self._silences = since_ms, 0

    def _service_ms(self, due: tuple[float, int]) -> float:
        """The due packet's time at the capacity estimate; with `fixed_due_time`, at the
        estimate when that packet was first found due (a later cut does not move it)."""
        service_ms = due[1] / self.capacity_kbps
        if not self.settings.fixed_due_time:
            return service_ms
        if self._due != due:
            self._due, self._due_service_ms = due, service_ms
        return self._due_service_ms

    def _bounded(self, target_kbps: float) -> float:
        """`target_kbps` within [min_kbps, max_kbps]: the one place the target is bounded
        (the engine follows it as it is)."""
        return min(max(target_kbps, self.settings.min_kbps), self.settings.max_kbps)

    def paused(self, now_ms: float) -> bool:
        """No report for `pause_ms`: the sender sends nothing new until one comes (a lost
        report costs a frame or two; a handover's gap or an outage gets none of the stream)."""
        quiet_ms = self.quiet_ms(now_ms)
        return self._overdue or (quiet_ms is not None and quiet_ms >= self.settings.pause_ms)

    def quiet_ms(self, now_ms: float) -> float | None:
        """How long no report has come (None: none yet)."""
        return None if self._quiet_since_ms is None else now_ms - self._quiet_since_ms

    def _received(self, report: DeliveryReport) -> None:
        span_ms = report.end_ms - report.start_ms
        if self.received_kbps is None:
            self.received_kbps = report.received_kbps
        elif span_ms > 0:
            weight = 1.0 - math.exp(-span_ms / self.settings.received_tau_ms)
            self.received_kbps += weight * (report.received_kbps - self.received_kbps)

    def on_silence(self, now_ms: float) -> RateDecision:
        """No report for `silence_ms` (an outage): x `silence_factor`, once per `silence_ms`
        of quiet, from the capacity or, when less came (an application-limited stream), from
        what arrived."""
        s = self.settings
        quiet_ms = self.quiet_ms(now_ms)
        if quiet_ms is not None and quiet_ms >= (self._silences + 1) * s.silence_ms:
            self._judge.on_cut(self.capacity_kbps, self._quiet_since_ms)
            limited = self.received_kbps is not None and (
                self.received_kbps < s.alr_fraction * self.capacity_kbps
            )
            if s.recover_after_silence and self._recover_kbps is None and limited:
                pre_cut_kbps = s.recover_fraction * self.capacity_kbps
                self._recover_kbps = max(pre_cut_kbps, self._recovering_kbps or 0.0)
                self._recover_until_ms = now_ms + s.recover_window_ms
                self._recovering_kbps = None
            base = self.capacity_kbps
            if self.received_kbps is not None:
                base = min(base, max(self.received_kbps, s.min_kbps))
            self.capacity_kbps = max(base * s.silence_factor, s.min_kbps)
            self.target_kbps = self._bounded(self.capacity_kbps * s.headroom)
            self._silences += 1
            return RateDecision(self.target_kbps, None, "silence")
        return RateDecision(self.target_kbps, None, "")

    def on_handover(self, technology: str, now_ms: float) -> RateDecision:
        """The link changed technology: its prior may lower the estimate; the trend restarts."""
        s = self.settings
        prior = s.priors_kbps.get(technology)
        self._reset_trend()
        self._judge.forget()  # the silence was the handover's gap: no undoing it
        self._base_ms = None  # the new path's delay is not known yet
        reason = "handover"
        if prior is not None and self._recovering_kbps is not None:
            self._recovering_kbps = min(self._recovering_kbps, prior)
        if prior is not None and self._recover_kbps is not None:
            self._recover_kbps = min(self._recover_kbps, prior)
        if prior is not None and prior < self.capacity_kbps:
            self.capacity_kbps = prior
            reason = "handover prior"
        self.target_kbps = self._bounded(self.capacity_kbps * s.headroom)
        self._last_train_ms = float("-inf")  # measure the new link soon
        return RateDecision(self.target_kbps, None, reason)

    def _target(self) -> tuple[float, str]:
        s = self.settings
        excess_ms = max(0.0, self.queue_ms - s.queue_target_ms)
        drain_kbps = self.capacity_kbps * excess_ms / s.drain_ms
        target = self.capacity_kbps * s.headroom - drain_kbps
        reason = "drain" if drain_kbps > 0 else "capacity"
        if self.usage is Usage.OVER and self.queue_ms > s.queue_low_ms:
            target *= s.beta
            reason = "trend"
        return target, reason

    def _probe(self, report: DeliveryReport, now_ms: float) -> ProbeRequest | None:
        s = self.settings
        limited = report.received_kbps < s.alr_fraction * self.target_kbps
        unmeasured = now_ms - self._last_train_ms >= s.probe_interval_ms
        idle = self.queue_ms < s.queue_target_ms
        if not ((limited or idle) and unmeasured):
            return None
        if s.no_probe_while_owed and self._owed:
            return None  # it would only wait behind what the link owes
        quiet_ms = self.quiet_ms(now_ms)
        if s.no_probe_into_silence and quiet_ms is not None and quiet_ms >= s.silence_ms:
            return None  # an outage, not an idle sender: the silence cut is due first
        if s.no_probe_while_paused and self.paused(now_ms):
            return None  # the link owes what is out: a probe would only queue behind it
        if now_ms - self._last_probe_ms < s.probe_interval_ms:
            return None
        self._last_probe_ms = now_ms
        self._probe_pending = True
        return self._sized_probe(self.capacity_kbps)

    def _sized_probe(self, rate_kbps: float) -> ProbeRequest:
        """Small and few packets on a slow link, so that a probe queues about `probe_ms` at
        `rate_kbps` (a train needs two): five 100-byte packets would hold GSM's 9.6 kbit/s
        for 0.4 s."""
        s = self.settings
        total_bits = rate_kbps * s.probe_ms
        packets = int(min(max(total_bits // s.probe_min_bits, 2), s.probe_packets))
        bits = int(min(max(total_bits / packets, s.probe_min_bits), s.packet_bits))
        return ProbeRequest(2.0 * rate_kbps, packets, bits)
