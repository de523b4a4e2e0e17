"""`engine.drained_queue`: once every packet sent has been reported, the queue the last report
measured is gone (hand-worked reports: a frame sent at 0 s came out 2 s later, behind 2 s of
queue; the next frame is judged at 2.12 s)."""

from __future__ import annotations

import pytest

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.config.engine import PacerConfig
from uma.control import DeliveryReport, PacketRecord
from uma.engine import OutgoingUnit, ReceiverReport, SendPacket, UmaEngine
from uma.engine.decisions import CodedReport
from uma.engine.points import OperatingPoint
from uma.engine.rate import make_rate

FRAME_BYTES = 500  # one packet: 4 kbit, 100 kbit/s at 25 frames/s


def _report(seq: int, *, reported_seq: int) -> ReceiverReport:
    """Packet `seq` (sent at 0 ms, 4 kbit) arrived at 2,020 ms, 2,000 ms after an idle link
    would have delivered it (the base one-way delay is 20 ms); the report names
    `reported_seq` as the highest packet received."""
    bits = FRAME_BYTES * 8
    delivery = DeliveryReport(
        start_ms=2000.0, end_ms=2100.0, packets=1, received_bits=bits, lost=0, train_bits=0,
        train_ms=0.0, queue_delay_ms=(2000.0,), records=(PacketRecord(seq, 0.0, 2020.0, bits),),
    )  # fmt: skip
    return ReceiverReport(2.1, 0.1, bits, 1, 0, reported_seq, 2000.0, delivery=delivery)


def _engine(drained: bool) -> UmaEngine:
    config = EngineConfig(
        estimator=EstimatorConfig(initial_kbps=300.0, queue_from_owed=False),  # this key alone
        pacer=PacerConfig(deadline_ms=1000.0),
        drained_queue=drained,
    )
    points = (OperatingPoint("h264", 100.0, 25.0, 176, 144, compute_ms=4.0),)
    return UmaEngine(config, points=points, source_fps=25.0, feedback=FeedbackConfig())


def _send(engine: UmaEngine, frame: int, now_s: float) -> list[SendPacket]:
    """A unit of `frame` handed to the engine at `now_s` and paced out at once: the packets
    that leave (the pacer runs at 2.5 x 300 kbit/s, its burst 40 ms of that)."""
    engine.on_coded(CodedReport(frame, 0, False), now_s)
    engine.on_sent(OutgoingUnit(None, FRAME_BYTES, 0, (frame,), False), now_s)
    decision = engine.on_pace(now_s)
    return [a for a in decision.sent if isinstance(a, SendPacket)]


@pytest.mark.parametrize(
    ("drained", "out_of_flight", "leaves"),
    [(False, True, False), (True, True, True), (True, False, False)],
)
def test_the_pacer_judges_a_deadline_on_the_queue_still_ahead(drained, out_of_flight, leaves):
    """Frame 53 (captured at 2.12 s, due on screen by 3.12 s) queued at 2.12 s after a report
    that measured 2 s of queue: taken as still there it would arrive at about 4.1 s and is
    dropped as too late (a keyframe must follow); with `drained_queue` and frame 0's packet
    reported it leaves, but not while that packet is still in flight (a second packet is
    outstanding: the queue it meets may stand)."""
    engine = _engine(drained)
    first = _send(engine, 0, 0.0)
    assert len(first) == 1
    if not out_of_flight:
        _send(engine, 1, 0.04)  # another packet in flight behind it
    engine.on_report(_report(first[0].seq, reported_seq=first[0].seq), 2.1)
    assert engine.estimator.queue_delay_ms == pytest.approx(2000.0)
    assert (engine.outstanding_bits == 0) is out_of_flight
    sent = _send(engine, 53, 2.12)
    dropped = [e for e in engine.events if e.kind == "pacer_drop"]
    assert bool(sent) is leaves
    assert bool(dropped) is not leaves


@pytest.mark.parametrize(("drained", "outstanding_bits", "skips"), [
    (False, 0, True), (True, 0, False), (True, 4000, True), (True, -1, True),
])  # fmt: skip
def test_uma_s_skip_rule_takes_no_queue_ahead_once_nothing_is_in_flight(
    drained, outstanding_bits, skips
):
    """After the report of 2 s of queue the estimate is 300 kbit/s: 2 s of it ahead (600 kbit)
    is past the skip budget (300 ms: 90 kbit), so a 4-kbit frame is skipped; with
    `drained_queue` and nothing in flight the queue ahead is none and it is coded. Bits
    still in flight (or not known: -1) keep the reported queue."""
    estimator = EstimatorConfig(initial_kbps=300.0, queue_from_owed=False)  # this key alone
    config = EngineConfig(estimator=estimator, drained_queue=drained)
    rate = make_rate(config, FeedbackConfig())
    rate.on_report(_report(0, reported_seq=0), 2.1)
    assert rate.controller.queue_ms == pytest.approx(2000.0)
    assert rate.skip(4000.0, 0.0, 2.12, outstanding_bits=outstanding_bits) is skips


def test_drained_queue_is_off_by_default_and_leaves_gcc_s_skips_alone():
    assert EngineConfig().drained_queue is False
    gcc = make_rate(
        EngineConfig(estimator=EstimatorConfig(kind="gcc"), drained_queue=True), FeedbackConfig()
    )
    assert gcc.skip(1e9, 1e9, 0.0, outstanding_bits=0) is False
