"""The injected link faults (`faults`): loss bursts, outages, reordering, feedback silence.

Units live in key names (`start_s`, `duration_s`, `delay_ms`); probabilities are fractions.
"""

from __future__ import annotations

from uma.config.types import Fraction, NonNeg, PosNum, Section

__all__ = [
    "LossBurstConfig",
    "OutageConfig",
    "ReorderConfig",
    "SilenceConfig",
    "FaultsConfig",
]


class LossBurstConfig(Section):
    """Gilbert-Elliott loss bursts: a good and a bad state, stepped once per packet leaving the
    downlink; a packet is lost with the state's probability (on top of the random loss)."""

    p_good_to_bad: Fraction = 0.01
    p_bad_to_good: Fraction = 0.3
    loss_good: Fraction = 0.0
    loss_bad: Fraction = 1.0


class OutageConfig(Section):
    """Zero downlink capacity from `start_s` for `duration_s` (it may outlast the run)."""

    start_s: NonNeg
    duration_s: PosNum


class ReorderConfig(Section):
    """Each packet, with `probability`, arrives `delay_ms` late and is overtaken by later ones."""

    probability: Fraction = 0.05
    delay_ms: PosNum = 50.0


class SilenceConfig(Section):
    """The feedback channel (reports, keyframe requests) carries nothing for a stretch."""

    start_s: NonNeg
    duration_s: PosNum


class FaultsConfig(Section):
    """Link faults injected into the run (see `uma.sim.faults`); none by default."""

    loss_bursts: LossBurstConfig | None = None
    outages: tuple[OutageConfig, ...] = ()
    reorder: ReorderConfig | None = None
    feedback_silence: tuple[SilenceConfig, ...] = ()
