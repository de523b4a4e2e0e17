import pytest

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.control import DeliveryReport, DeliverySettings, DeliveryTracker
from uma.engine import CodedReport, KeyframeRequest, ReceiverReport, SendPacket, UmaEngine
from uma.engine.points import OperatingPoint

RATES = (30.0, 100.0, 300.0, 1000.0)
FPS = (5.0, 12.5, 25.0, 25.0)


def make_engine(**engine_kw):
    config = EngineConfig(estimator=EstimatorConfig(initial_kbps=400.0), safety=1.0, **engine_kw)
    return UmaEngine(
        config,
        points=tuple(
            OperatingPoint("h264", rate, fps, 176, 144, compute_ms=4.0)
            for rate, fps in zip(RATES, FPS, strict=True)
        ),
        source_fps=25.0,
        feedback=FeedbackConfig(interval_ms=100.0, keyframe_min_interval_ms=300.0),
    )


def in_flight(engine: UmaEngine, sizes_bits: list[int], now_s: float = 0.0) -> list[SendPacket]:
    """Packets of `sizes_bits` through the engine's send path (numbered, in flight at
    `now_s`)."""
    packets = [
        SendPacket("padding", None, i, len(sizes_bits), s, -1) for i, s in enumerate(sizes_bits)
    ]
    return engine.outbox.number(packets, now_s)


def coded(engine: UmaEngine, decision, now_s: float, **outcome) -> list:
    """Report that the world coded `decision`'s frame (an intra picture when it was asked)."""
    keyframe = outcome.pop("keyframe", decision.keyframe)
    report = CodedReport(decision.frame, decision.rung, keyframe=keyframe, **outcome)
    return engine.on_coded(report, now_s)


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
    decision = engine.on_frame(25, 1.0)
    assert decision.force_idr and decision.keyframe
    coded(engine, decision, 1.0)  # the world reports the IDR left
    assert not engine.on_frame(26, 1.04).force_idr
    engine.on_keyframe_request(KeyframeRequest(sent_s=1.1, frame=5), 1.1)
    assert not engine.on_frame(27, 1.1).force_idr  # too soon after the last IDR
    assert engine.on_frame(35, 1.4).force_idr


def test_keyframe_request_survives_a_frame_that_was_never_coded():
    # The engine could not decode the picture, so no IDR left: the request must stay pending.
    engine = make_engine(policy="fixed", fixed_rung=3)
    engine.on_keyframe_request(KeyframeRequest(sent_s=1.0, frame=3), 1.0)
    assert engine.on_frame(25, 1.0, decoded=False).force_idr  # ...no picture to code
    decision = engine.on_frame(26, 1.04)
    assert decision.force_idr
    coded(engine, decision, 1.04, keyframe=False)  # the coder made no IDR: still pending
    decision = engine.on_frame(27, 1.08)
    assert decision.force_idr
    coded(engine, decision, 1.08)
    assert not engine.on_frame(28, 1.5).force_idr


def delivered(seq0: int, count: int, *, send_ms: float, gap_ms: float, bits: int = 8000,
              base_ms: float = 20.0) -> DeliveryReport:  # fmt: skip
    """A report of `count` packets sent together at `send_ms` that arrived `gap_ms` apart
    (a train measuring bits / gap_ms kbit/s)."""
    tracker = DeliveryTracker(DeliverySettings(interval_ms=1e9))  # closed by `flush` only
    for k in range(count):
        tracker.on_packet(seq0 + k, send_ms, send_ms + base_ms + k * gap_ms, bits)
    return tracker.flush(send_ms + base_ms + count * gap_ms)


def test_switch_down_within_a_size_retargets_without_a_keyframe_and_is_logged():
    engine = make_engine()
    coded(engine, engine.on_frame(0, 0.0), 0.0)  # the stream is open at rung 2
    in_flight(engine, [8000] * 10)
    train = delivered(0, 10, send_ms=0.0, gap_ms=200.0)  # 40 kbit/s
    report = ReceiverReport(0.1, 0.1, 80_000, 10, 0, 9, 5.0, delivery=train)
    engine.on_report(report, 0.15)
    assert engine.estimate_kbps < 100.0
    decision = engine.on_frame(4, 0.16)
    assert decision.rung == 0 and not decision.force_idr and not decision.keyframe
    assert decision.target_kbps == 30.0  # the open encoder is aimed at the rung's rate
    assert [e.kind for e in engine.events] == ["rung_switch"]


def test_a_switch_to_another_size_is_a_new_stream_with_a_keyframe():
    config = EngineConfig(estimator=EstimatorConfig(initial_kbps=400.0), safety=1.0)
    points = (
        OperatingPoint("h264", 30.0, 12.5, 176, 144, compute_ms=4.0),
        OperatingPoint("h264", 300.0, 25.0, 352, 288, compute_ms=4.0),
    )
    engine = UmaEngine(config, points=points, source_fps=25.0, feedback=FeedbackConfig())
    first = engine.on_frame(0, 0.0)
    assert first.rung == 1 and first.keyframe  # the first frame opens the stream
    coded(engine, first, 0.0)
    report = ReceiverReport(
        0.1, 0.1, 80_000, 10, 0, 9, 5.0, delivery=delivered(0, 10, send_ms=0.0, gap_ms=200.0)
    )
    engine.on_report(report, 0.15)
    decision = engine.on_frame(5, 0.2)
    assert decision.rung == 0 and decision.force_idr and decision.keyframe
    assert decision.target_kbps is None


def test_backlog_skips_frames_until_reports_catch_up():
    engine = make_engine(policy="fixed", fixed_rung=3)
    assert engine.on_frame(0, 0.0).send
    in_flight(engine, [12_000] * 20)  # 240 kbit outstanding, more than 0.3 s at 400 kbit/s
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
    in_flight(engine, [12_000] * 20)
    assert not engine.on_frame(1, 0.5).send
    assert engine.on_frame(25, 1.0).send  # probe after a second without sending
    engine.on_frame(26, 2.5)  # no report progress for over 2 s: presumed lost
    assert engine.outstanding_bits == 0


def _report(now_s, *, bits=20000, packets=2, highest_seq=0, delivery=None):
    return ReceiverReport(
        sent_s=now_s,
        interval_s=0.1,
        received_bits=bits,
        packets_received=packets,
        packets_lost=0,
        highest_seq=highest_seq,
        queue_delay_ms=0.0,
        delivery=delivery,
    )


def test_silent_feedback_lowers_the_estimate_once_per_silence_interval():
    """No report for 250 ms (the controller's `silence_ms`): the estimate x0.25, once each."""
    engine = make_engine()
    train = delivered(0, 10, send_ms=0.0, gap_ms=20.0)  # 400 kbit/s
    engine.on_report(_report(0.1, delivery=train), 0.1)
    before = engine.estimate_kbps
    engine.on_frame(3, 0.3)  # 200 ms without a report: not yet silent
    assert engine.estimate_kbps == before
    engine.on_frame(9, 0.36)
    assert engine.estimate_kbps == pytest.approx(before * 0.25, rel=0.01)
    engine.on_frame(10, 0.4)  # once per interval
    assert engine.estimate_kbps == pytest.approx(before * 0.25, rel=0.01)
    assert [e.kind for e in engine.events if e.kind == "silence"] == ["silence"]


def test_without_any_report_the_estimate_stays_the_initial_one():
    engine = make_engine()
    estimate = engine.estimate_kbps
    engine.on_frame(50, 2.0)
    assert engine.estimate_kbps == estimate == 400.0


def test_report_naming_a_sequence_never_sent_is_clamped():
    engine = make_engine()
    in_flight(engine, [8000, 8000])
    engine.on_report(_report(0.1, highest_seq=99), 0.1)
    assert engine.inflight.highest_seq == 1 and engine.outstanding_bits == 0
    engine.on_frame(3, 0.12)


# --- switching to the model-based codec -------------------------------------------------------
def make_switching_engine(*, model_unavailable="", **switching):
    from uma.config.scenario import SwitchingConfig

    settings = {"policy": "threshold", "min_dwell_ms": 0.0} | switching
    config = EngineConfig(
        estimator=EstimatorConfig(initial_kbps=400.0),
        safety=1.0,
        policy="oracle",
        switching=SwitchingConfig(**settings),
    )
    points = (OperatingPoint("mbc", 4.8, 25.0, 176, 144, compute_us_per_evaluation=260.0),) + tuple(
        OperatingPoint("h264", rate, fps, 176, 144, compute_ms=4.0)
        for rate, fps in zip(RATES, FPS, strict=True)
    )
    return UmaEngine(
        config,
        points=points,
        source_fps=25.0,
        feedback=FeedbackConfig(interval_ms=100.0, keyframe_min_interval_ms=300.0),
        model_unavailable=model_unavailable,
    )


def test_switch_to_mbc_waits_for_the_initialisation_then_sends_intra():
    engine = make_switching_engine()
    first = engine.on_frame(0, 0.0, capacity_kbps=10.0)
    assert (
        first.initialise is not None and first.codec == "h264" and first.rung == 1
    )  # lowest H.264
    # Until the world reports the initialisation done, frames stay H.264, no second init.
    second = engine.on_frame(1, 0.04, capacity_kbps=10.0)
    assert second.codec == "h264" and second.initialise is None
    engine.on_init_done(True, 0.06, reason="first picture", evaluations=600)
    third = engine.on_frame(2, 0.08, capacity_kbps=10.0)
    assert third.codec == "mbc" and third.force_idr and third.send
    assert third.point.compute_s(7) == pytest.approx(7 * 260e-6)
    # Capacity back: H.264 at the rung the oracle picks, with an IDR.
    back = engine.on_frame(3, 0.12, capacity_kbps=2000.0)
    assert back.codec == "h264" and back.rung == 4 and back.force_idr
    kinds = [e.kind for e in engine.events]
    assert kinds.count("codec_switch") == 2 and "mbc_init_done" in kinds


def test_the_model_codec_at_one_point_is_one_stream_intra_only_when_it_starts():
    # Before: every model-codec frame was a "new stream" (only full-frame codecs are
    # retargeted), so every parameter packet started intra (twice the bits of a predicted one).
    engine = make_switching_engine()
    engine.on_frame(0, 0.0, capacity_kbps=10.0)
    engine.on_init_done(True, 0.05, evaluations=600)
    first = engine.on_frame(2, 0.08, capacity_kbps=10.0)
    assert first.codec == "mbc" and first.keyframe
    coded(engine, first, 0.09)
    later = [engine.on_frame(i, i / 25.0, capacity_kbps=10.0) for i in range(3, 8)]
    for decision in later:
        coded(engine, decision, decision.frame / 25.0 + 0.01, keyframe=False)
    assert all(d.codec == "mbc" and d.send for d in later)
    assert not any(d.keyframe or d.force_idr for d in later)


def test_failed_initialisation_stays_on_the_lowest_rung_and_retries_later():
    engine = make_switching_engine(retry_ms=1000.0)
    assert engine.on_frame(0, 0.0, capacity_kbps=10.0).initialise is not None
    engine.on_init_done(False, 0.2, reason="no face found")
    decision = engine.on_frame(5, 0.2, capacity_kbps=10.0)
    assert decision.codec == "h264" and decision.rung == 1 and decision.initialise is None
    assert engine.on_frame(6, 0.9, capacity_kbps=10.0).initialise is None  # before retry_ms
    assert engine.on_frame(30, 1.3, capacity_kbps=10.0).initialise is not None
    failed = [e for e in engine.events if e.kind == "mbc_init_failed"]
    assert failed and "no face found" in failed[0].detail
    assert engine.counts["init_failures"] == 1 and engine.counts["inits"] == 2


def test_no_description_keeps_the_lowest_rung_and_says_why_once():
    engine = make_switching_engine(model_unavailable="no content description")
    decisions = [engine.on_frame(i, i / 25.0, capacity_kbps=10.0) for i in range(50)]
    assert all(d.codec == "h264" and d.rung == 1 and d.initialise is None for d in decisions)
    refused = [e for e in engine.events if e.kind == "mbc_refused"]
    assert len(refused) == 1 and "no content description" in refused[0].detail


def test_tracking_failure_falls_back_to_h264():
    engine = make_switching_engine()
    engine.on_frame(0, 0.0, capacity_kbps=10.0)
    engine.on_init_done(True, 0.05, evaluations=600)
    assert engine.on_frame(2, 0.08, capacity_kbps=10.0).codec == "mbc"
    third = engine.on_frame(3, 0.09, capacity_kbps=10.0)
    coded(engine, third, 0.1, failure="face left the picture")
    decision = engine.on_frame(4, 0.16, capacity_kbps=10.0)  # 5 frames/s: frame 4 is sent
    assert decision.codec == "h264" and decision.rung == 1 and decision.force_idr


def test_mbc_holds_frames_in_an_outage_but_probes():
    from uma.engine.reports import ReceiverReport

    engine = make_switching_engine()
    engine.on_frame(0, 0.0, capacity_kbps=10.0)
    engine.on_init_done(True, 0.05, evaluations=600)
    report = ReceiverReport(
        sent_s=0.05,
        interval_s=0.1,
        received_bits=0,
        packets_received=0,
        packets_lost=0,
        highest_seq=-1,
        queue_delay_ms=None,
    )
    engine.on_report(report, 0.06)
    sent = [engine.on_frame(i, i / 25.0, capacity_kbps=10.0) for i in range(2, 100)]
    assert all(d.codec == "mbc" for d in sent)
    # Reports stopped at 0.06 s: frames flow for `outage_hold_ms` (1 s: a handover gap's
    # parameters are still in time), then only a probe each `probe_interval_ms` (1 s).
    sent_s = [i / 25.0 for i, d in zip(range(2, 100), sent, strict=True) if d.send]
    assert max(t for t in sent_s if t < 1.5) == pytest.approx(1.04)
    late = [t for t in sent_s if t > 1.1]
    assert late and all(b - a >= 1.0 - 1e-9 for a, b in zip(late, late[1:], strict=False))
    assert all(d.reason == "backlog" for d in sent if not d.send)
