from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.engine import KeyframeRequest, ReceiverReport, UmaEngine

RATES = (30.0, 100.0, 300.0, 1000.0)
FPS = (5.0, 12.5, 25.0, 25.0)


def make_engine(**engine_kw):
    config = EngineConfig(estimator=EstimatorConfig(initial_kbps=400.0), safety=1.0, **engine_kw)
    return UmaEngine(
        config,
        rung_rates_kbps=RATES,
        rung_fps=FPS,
        source_fps=25.0,
        feedback=FeedbackConfig(interval_ms=100.0, keyframe_min_interval_ms=300.0),
    )


def test_starts_at_rung_the_initial_estimate_carries():
    assert make_engine().rung == 2


def test_frame_rate_decimation_keeps_the_right_share():
    engine = make_engine(policy="fixed", fixed_rung=0)
    kept = [engine.on_frame(i, i / 25.0).scheduled for i in range(100)]
    assert sum(kept) == 20  # 5 of every 25
    engine = make_engine(policy="fixed", fixed_rung=1)
    kept = [engine.on_frame(i, 0.0).scheduled for i in range(100)]
    assert sum(kept) == 50


def test_keyframe_request_forces_idr_once_and_respects_min_interval():
    engine = make_engine(policy="fixed", fixed_rung=3)
    engine.on_keyframe_request(KeyframeRequest(sent_s=1.0, frame=3), 1.0)
    assert engine.on_frame(25, 1.0).force_idr
    assert not engine.on_frame(26, 1.04).force_idr
    engine.on_keyframe_request(KeyframeRequest(sent_s=1.1, frame=5), 1.1)
    assert not engine.on_frame(27, 1.1).force_idr  # too soon after the last IDR
    assert engine.on_frame(35, 1.4).force_idr


def test_switch_down_forces_idr_and_is_logged():
    engine = make_engine()
    engine.on_packets_sent([8000] * 10)
    report = ReceiverReport(
        sent_s=0.1,
        interval_s=0.1,
        received_bits=5000,
        packets_received=5,
        packets_lost=0,
        highest_seq=4,
        queue_delay_ms=500.0,
    )
    engine.on_report(report, 0.15)
    decision = engine.on_frame(4, 0.16)
    assert decision.rung == 0 and decision.force_idr
    assert [e.kind for e in engine.events] == ["rung_switch"]


def test_backlog_skips_frames_until_reports_catch_up():
    engine = make_engine(policy="fixed", fixed_rung=3)
    assert engine.on_frame(0, 0.0).send
    engine.on_packets_sent([12_000] * 20)  # 240 kbit outstanding, more than 0.3 s at 400 kbit/s
    decision = engine.on_frame(1, 0.04)
    assert decision.scheduled and not decision.send and decision.reason == "backlog"
    report = ReceiverReport(
        sent_s=0.1,
        interval_s=0.1,
        received_bits=240_000,
        packets_received=20,
        packets_lost=0,
        highest_seq=19,
        queue_delay_ms=5.0,
    )
    engine.on_report(report, 0.1)
    assert engine.outstanding_bits == 0
    assert engine.on_frame(2, 0.08).send


def test_backlogged_engine_still_probes_and_presumes_old_packets_lost():
    engine = make_engine(policy="fixed", fixed_rung=3)
    assert engine.on_frame(0, 0.0).send
    engine.on_packets_sent([12_000] * 20)
    assert not engine.on_frame(1, 0.5).send
    assert engine.on_frame(25, 1.0).send  # probe after a second without sending
    engine.on_frame(26, 2.5)  # no report progress for over 2 s: presumed lost
    assert engine.outstanding_bits == 0


def test_missing_reports_decay_the_estimate():
    engine = make_engine()
    before = engine.estimate_kbps
    engine.on_frame(0, 1.0)
    assert engine.estimate_kbps < before


def _report(now_s, *, bits=20000, packets=2, highest_seq=0):
    return ReceiverReport(
        sent_s=now_s,
        interval_s=0.1,
        received_bits=bits,
        packets_received=packets,
        packets_lost=0,
        highest_seq=highest_seq,
        queue_delay_ms=0.0,
    )


def test_silent_feedback_decays_the_estimate_but_keeps_its_window():
    engine = make_engine(stale_reports=3)
    engine.on_packets_sent([8000, 8000])
    for i in range(10):
        engine.on_report(_report(i / 10, highest_seq=1), i / 10)
    before = engine.estimator
    engine.on_frame(50, 2.0)  # reports stopped 1.1 s ago: stale
    after = engine.estimator
    assert after.estimate_kbps == before.estimate_kbps * 0.85
    assert after.window == before.window and after.received_kbps == before.received_kbps
    assert after.last_decrease_s == 2.0


def test_stale_threshold_is_configurable():
    engine = make_engine(stale_reports=30)
    estimate = engine.estimate_kbps
    engine.on_frame(50, 2.0)  # 20 intervals without a report: not yet stale
    assert engine.estimate_kbps == estimate


def test_report_naming_a_sequence_never_sent_is_clamped():
    engine = make_engine()
    engine.on_packets_sent([8000, 8000])
    engine.on_report(_report(0.1, highest_seq=99), 0.1)
    assert engine.highest_seq == 1 and engine.outstanding_bits == 0
    engine.on_frame(3, 0.12)
