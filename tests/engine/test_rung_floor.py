"""`engine.rung_floor`: an estimate cut below the lowest rung does not starve the sender
(hand-worked: the ladder's lowest rung is 16 kbit/s at 5 frames/s, 3.2 kbit a frame; the
estimate is the controller's floor, 5 kbit/s)."""

from __future__ import annotations

import pytest

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.control import DeliveryReport, PacketRecord
from uma.engine import OutgoingUnit, ReceiverReport, UmaEngine
from uma.engine.decisions import CodedReport
from uma.engine.points import OperatingPoint
from uma.engine.sending import HEADER_BYTES

FRAME_BYTES = 400  # 3.2 kbit: the lowest rung's share of a second at 5 frames/s
POINTS = (
    OperatingPoint("h264", 16.0, 5.0, 128, 96, compute_ms=4.0),
    OperatingPoint("h264", 64.0, 12.5, 256, 208, compute_ms=4.0),
)


def _engine(floor: bool, kind: str = "uma") -> UmaEngine:
    config = EngineConfig(
        estimator=EstimatorConfig(kind=kind, initial_kbps=5.0, min_kbps=5.0), rung_floor=floor
    )
    return UmaEngine(config, points=POINTS, source_fps=25.0, feedback=FeedbackConfig())


def _coded(engine: UmaEngine, frame: int, now_s: float) -> None:
    """The world codes `frame` (3.2 kbit) and hands its unit on; the pacer runs."""
    engine.on_coded(CodedReport(frame, 0, False), now_s)
    engine.on_sent(OutgoingUnit(None, FRAME_BYTES, 0, (frame,), False), now_s)
    engine.on_pace(now_s)


def _frames(engine: UmaEngine, frames: tuple[int, ...]) -> list[str]:
    """Each frame decided at its capture time (25 frames/s) and, when sent, coded: why not."""
    reasons = []
    for frame in frames:
        now_s = frame / 25.0
        decision = engine.on_frame(frame, now_s)
        reasons.append("send" if decision.send else decision.reason)
        if decision.send:
            _coded(engine, frame, now_s)
    return reasons


def test_the_floor_is_the_lowest_skippable_rung_and_on_by_default():
    assert EngineConfig().rung_floor is True
    assert _engine(False).rate.floor_kbps == 0.0
    assert _engine(True).rate.floor_kbps == 16.0


def test_without_the_floor_an_estimate_below_the_lowest_rung_skips_its_frames():
    """At 5 kbit/s the skip budget (300 ms) holds 1.5 kbit: every 3.2-kbit frame the rung's
    5 frames/s keep (4, 9, 14, ...) is skipped until the skip limit (1 s after the first
    skip, at 0.16 s) forces one."""
    engine = _engine(False)
    assert engine.rung == 0
    assert _frames(engine, (4, 9, 14, 19, 24, 29, 34)) == ["skip"] * 6 + ["send"]


def test_with_the_floor_the_lowest_rung_is_held_by_the_backlog_alone():
    """The lowest rung is never skipped; the backlog hold judges at 16 kbit/s, not 5: 300 ms of
    it is 4.8 kbit, so frame 4 (nothing ahead) and frame 9 (3.52 kbit ahead: a frame and its
    packet's 40-byte header) are sent and frame 14 (7.04 kbit ahead) is held; at 5 kbit/s
    (1.5 kbit) frame 9 would be held."""
    engine = _engine(True)
    assert _frames(engine, (4, 9, 14)) == ["send", "send", "backlog"]
    assert engine.outstanding_bits + engine.queued_bits == 2 * (FRAME_BYTES + HEADER_BYTES) * 8


def _report(now_ms: float) -> ReceiverReport:
    """A report at `now_ms` of one packet that met no queue (the estimate stays 5 kbit/s)."""
    bits = 800
    delivery = DeliveryReport(
        start_ms=now_ms - 100.0, end_ms=now_ms, packets=1, received_bits=bits, lost=0,
        train_bits=0, train_ms=0.0, queue_delay_ms=(0.0,),
        records=(PacketRecord(0, now_ms - 30.0, now_ms - 10.0, bits),),
    )  # fmt: skip
    return ReceiverReport(now_ms / 1000.0, 0.1, bits, 1, 0, 0, 20.0, delivery=delivery)


@pytest.mark.parametrize(("floor", "rung", "skips"), [
    (False, 0, True), (True, 0, False), (True, 1, True), (False, 1, True),
])  # fmt: skip
def test_a_pause_skips_every_rung_but_the_floor(floor, rung, skips):
    """A report at 100 ms, none since: at 400 ms the controller is paused (no report for its
    150 ms), so a frame is not coded, whatever fits; with the floor the lowest rung's frame
    still is (its backlog rule holds it), a higher rung's is not."""
    engine = _engine(floor)
    engine.on_report(_report(100.0), 0.1)
    assert engine.rate.paused(0.4)
    assert engine.rate.skips_frame(POINTS[rung], 0, 0.4, 0) is skips


def test_the_oracle_and_gcc_hold_as_before_but_for_the_floor_s_rate():
    """The backlog gate reads the true capacity when given (the oracle's) and otherwise the
    estimate at no less than the floor, for every kind; gcc never skips."""
    gcc = _engine(True, kind="gcc")
    assert gcc.rate.gate_kbps(5.0) == 16.0
    assert gcc.rate.gate_kbps(5.0, 2.0) == 2.0
    assert _engine(False, kind="gcc").rate.gate_kbps(5.0) == 5.0
    assert gcc.rate.skips_frame(POINTS[1], 10**9, 0.0, 10**9) is False
