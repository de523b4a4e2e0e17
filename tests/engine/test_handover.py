"""Handover awareness on scripted reports: the estimate takes the new technology's prior."""

import pytest

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.engine import ReceiverReport, UmaEngine
from uma.engine.handover import Handover
from uma.engine.points import OperatingPoint

PRIORS = {"3G": 800.0, "GPRS": 35.0, "GSM": 9.6}


def _engine(enabled: bool) -> UmaEngine:
    config = EngineConfig(
        estimator=EstimatorConfig(initial_kbps=700.0), handover={"enabled": enabled}
    )
    points = tuple(OperatingPoint("h264", r, 25.0, 176, 144, 4.0) for r in (30.0, 100.0, 600.0))
    return UmaEngine(
        config, points=points, source_fps=25.0, feedback=FeedbackConfig(),
        technology_priors_kbps=PRIORS,
    )  # fmt: skip


def _report(t_s: float, kbps: float, technology: str, queue_ms: float = 5.0) -> ReceiverReport:
    return ReceiverReport(
        sent_s=t_s, interval_s=0.1, received_bits=int(kbps * 100), packets_received=5,
        packets_lost=0, highest_seq=-1, queue_delay_ms=queue_ms, technology=technology,
    )  # fmt: skip


def test_the_first_report_names_the_technology_without_a_handover():
    handover = Handover(PRIORS)
    assert handover.on_report("3G") is None
    assert handover.on_report("3G") is None
    assert handover.on_report("GPRS") == 35.0
    assert handover.on_report("") is None  # a receiver that does not say keeps the last
    assert handover.on_report("LTE") is None  # no prior known: learnt as before


@pytest.mark.parametrize("enabled", [True, False])
def test_a_handover_to_gprs_drops_the_estimate_at_once(enabled):
    engine = _engine(enabled)
    for i in range(10):
        engine.on_report(_report(0.1 * i, 600.0, "3G"), 0.1 * i)
    before_kbps = engine.estimate_kbps
    # The first GPRS report: little received yet, the bottleneck still full of 3G's bits.
    engine.on_report(_report(1.1, 300.0, "GPRS", queue_ms=120.0), 1.1)
    decision = engine.on_frame(28, 1.12)
    if enabled:
        assert engine.estimate_kbps == pytest.approx(35.0)
        assert decision.rung == 0
        assert [e.kind for e in engine.events][:1] == ["handover_prior"]
    else:
        assert engine.estimate_kbps >= 0.85 * before_kbps
        assert "handover_prior" not in [e.kind for e in engine.events]
