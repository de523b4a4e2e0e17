"""Handover awareness: the access technology the receiver reports, and its prior capacity.

Units: rates in kbit/s, times in seconds.

A receiver knows which radio it is on; its reports carry it. When that changes, the engine
need not learn the new link from a draining queue (seconds at the old rate into a slower
link): it takes the new technology's prior capacity as its estimate at once, and the
switching policy acts on that estimate as on any other. The priors come from the world (the
technologies' rate models, overridden by `engine.handover.priors_kbps`), never from the
engine's own imports. The report window is started afresh, so the old link's throughput is
not judged against the new one's.
"""

from __future__ import annotations

from dataclasses import replace

from uma.engine.estimator import EstimatorState
from uma.engine.records import EngineEvent

__all__ = ["Handover", "handover_estimate"]


def handover_estimate(
    state: EstimatorState, prior_kbps: float, *, now_s: float, min_kbps: float, max_kbps: float
) -> EstimatorState:
    """`state` after a handover to a technology of `prior_kbps`: the prior is the estimate."""
    return replace(
        state,
        estimate_kbps=min(max(prior_kbps, min_kbps), max_kbps),
        last_decrease_s=now_s,
        window=(),
        delays=(),
        trend_ms_per_s=0.0,
    )


class Handover:
    """The technology last reported, and the prior to take when it changes."""

    def __init__(self, priors_kbps: dict[str, float]) -> None:
        self.priors_kbps = dict(priors_kbps)
        self.technology: str | None = None

    def on_report(self, technology: str | None) -> float | None:
        """The prior to take now (None: no handover, the first report, or no prior known)."""
        if not technology or technology == self.technology:
            return None
        first = self.technology is None
        self.technology = technology
        return None if first else self.priors_kbps.get(technology)

    def take_prior(
        self, state: EstimatorState, technology: str | None, *, now_s: float, config
    ) -> tuple[EstimatorState, list[EngineEvent]]:
        """The estimate after a report naming `technology` (`config`: `engine.estimator`):
        on a change, that technology's prior capacity, and the event saying so."""
        prior_kbps = self.on_report(technology)
        if prior_kbps is None:
            return state, []
        state = handover_estimate(
            state, prior_kbps, now_s=now_s, min_kbps=config.min_kbps, max_kbps=config.max_kbps
        )
        return state, [EngineEvent(now_s, "handover_prior", f"{technology} {prior_kbps:.1f} kbps")]
