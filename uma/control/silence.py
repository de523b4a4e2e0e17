"""A silence judged by the reports that end it: undo its cut when the link proved it spurious.

Units: kbit/s, ms. The controller cuts its capacity estimate while the feedback is silent (an
outage, a handover's gap, a lost report: it cannot tell which while it lasts). The estimate
before the first cut is held here until a report with packets says what the silence was:

- packets that met no queue (below `queue_low_ms`) and no loss: nothing was held up, the
  silence was a lost report (RFC 4015's spurious timeout): the held estimate is restored;
- with `judge_silence` (off by default: docs/rate-control.md, branch rc22), on the same path
  (the report names no new technology): packets that came out as a train at `judge_fraction`
  of the held estimate or more, no loss, within `judge_window_ms` of the silence's start: the
  link was off for a moment and then delivered the backlog at its old rate (an on/off link's
  off-period), so the held estimate is restored too (the queue the packets met is drained by
  the target's own drain term); packets without a train, within the window: the next report
  judges; a train below that, or a report after the window: the cut stands (the link came
  back slower, or the outage was long);
- a loss, or a handover (`forget`: a new path's packets say nothing of the old one's rate):
  the cut stands.
"""

from __future__ import annotations

from dataclasses import dataclass

from uma.control.delivery import DeliveryReport
from uma.control.settings import UmaSettings

__all__ = ["SilenceJudge"]


@dataclass
class SilenceJudge:
    """The capacity estimate before a silence's first cut, until a report judges the silence."""

    held_kbps: float | None = None
    since_ms: float = 0.0  # when the silence began (its quiet clock's start)

    def on_cut(self, capacity_kbps: float, quiet_since_ms: float) -> None:
        """A silence cut from `capacity_kbps`: held unless an earlier cut is still unjudged
        (the estimate before the first of them is what a verdict restores)."""
        if self.held_kbps is None:
            self.held_kbps, self.since_ms = capacity_kbps, quiet_since_ms

    def forget(self) -> None:
        """No verdict: the cut stands (a handover's gap)."""
        self.held_kbps = None

    def verdict(
        self, report: DeliveryReport, settings: UmaSettings, *, handover: bool = False
    ) -> float | None:
        """The estimate to restore after `report` (None: none now); decides, or waits for a
        report that can (one with no packet, or packets without a train, says nothing).
        `handover`: the report names a new technology (its train judges no silence)."""
        held = self.held_kbps
        if held is None or not report.queue_delay_ms:
            return None
        if report.lost:
            self.held_kbps = None
            return None
        if min(report.queue_delay_ms) < settings.queue_low_ms:
            self.held_kbps = None
            return held
        late = report.end_ms - self.since_ms > settings.judge_window_ms
        if not settings.judge_silence or handover or late:
            self.held_kbps = None
            return None
        if report.capacity_kbps is None:
            return None  # queued packets, no train: the next report may measure the drain
        self.held_kbps = None
        return held if report.capacity_kbps >= settings.judge_fraction * held else None
