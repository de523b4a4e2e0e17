"""Link faults from the scenario's `faults:` section: loss bursts, outages, reordering, silence.

Units: times in seconds (configs in s and ms as named), probabilities as fractions.
Draws come from their own random stream (the fourth child of the scenario's seed), so a
scenario without faults runs exactly as before and one with them is still reproducible.

- Loss bursts: Gilbert-Elliott, a two-state Markov chain stepped once per packet leaving the
  downlink; the bad state loses `loss_bad` of its packets, the good state `loss_good`.
- Outages: zero capacity for a stretch, folded into the capacity schedule (one that outlasts
  the run leaves the queue stranded, which the link counts at the end).
- Reordering: a packet held back `delay_ms` in the network is overtaken by later packets.
- Feedback silence: reports and keyframe requests sent in the stretch are lost.
"""

from __future__ import annotations

import numpy as np

from uma.config.scenario import FaultsConfig, OutageConfig
from uma.sim.capacity import CapacitySchedule

__all__ = ["Faults", "with_outages", "fault_rng"]


def fault_rng(seed: int) -> np.random.Generator:
    """The faults' own stream: child 3 of the seed (children 0-2 are route, loss, feedback)."""
    return np.random.default_rng(np.random.SeedSequence(seed).spawn(4)[3])


def with_outages(capacity: CapacitySchedule, outages: tuple[OutageConfig, ...]) -> CapacitySchedule:
    """`capacity` with zero rate during each outage; technology labels are kept."""
    if not outages:
        return capacity
    starts = capacity.starts_s
    cuts = [(o.start_s, o.start_s + o.duration_s) for o in outages]
    points = np.unique(np.concatenate([starts] + [np.array(c, dtype=np.float64) for c in cuts]))
    index = np.searchsorted(starts, points, side="right") - 1
    rates = capacity.rates_bps[index].copy()
    for begin, end in cuts:
        rates[(points >= begin) & (points < end)] = 0.0
    techs = [capacity.technologies[i] for i in index]
    return CapacitySchedule(points, rates, techs)


class Faults:
    """The faults' state during one run; the links and the feedback path ask it."""

    def __init__(self, config: FaultsConfig, *, rng: np.random.Generator) -> None:
        self.config = config
        self.rng = rng
        self.bad = False  # Gilbert-Elliott state

    @property
    def active(self) -> bool:
        c = self.config
        return bool(c.loss_bursts or c.outages or c.reorder or c.feedback_silence)

    def burst_lost(self) -> bool:
        """Step the Gilbert-Elliott chain for one packet; True when the packet is lost."""
        bursts = self.config.loss_bursts
        if bursts is None:
            return False
        flip = bursts.p_bad_to_good if self.bad else bursts.p_good_to_bad
        if self.rng.random() < flip:
            self.bad = not self.bad
        loss = bursts.loss_bad if self.bad else bursts.loss_good
        return bool(loss > 0.0 and self.rng.random() < loss)

    def reorder_delay_s(self) -> float:
        """Extra network delay of one packet: `delay_ms` with `probability`, else 0."""
        reorder = self.config.reorder
        if reorder is None or reorder.probability <= 0.0:
            return 0.0
        return reorder.delay_ms / 1000.0 if self.rng.random() < reorder.probability else 0.0

    def feedback_silent(self, t_s: float) -> bool:
        return any(
            s.start_s <= t_s < s.start_s + s.duration_s for s in self.config.feedback_silence
        )
