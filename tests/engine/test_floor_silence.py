"""`engine.floor_silence_skip`: with the rung floor, the lowest rung's frames are skipped too
in a silent pause (hand-worked: the lowest rung is 16 kbit/s at 5 frames/s, 3.2 kbit a frame;
the skip limit is 1 s, so the link is silent for that frame while what arrived over the last
second is below 3.2 kbit/s)."""

from __future__ import annotations

import pytest

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.control import DeliveryReport, PacketRecord
from uma.engine import ReceiverReport, UmaEngine
from uma.engine.points import OperatingPoint

POINTS = (
    OperatingPoint("h264", 16.0, 5.0, 128, 96, compute_ms=4.0),
    OperatingPoint("h264", 64.0, 12.5, 256, 208, compute_ms=4.0),
)


def _engine(skip: bool, *, floor: bool = True, kind: str = "uma") -> UmaEngine:
    config = EngineConfig(
        estimator=EstimatorConfig(kind=kind, initial_kbps=5.0, min_kbps=5.0),
        rung_floor=floor, floor_silence_skip=skip,
    )  # fmt: skip
    return UmaEngine(config, points=POINTS, source_fps=25.0, feedback=FeedbackConfig())


def _report(now_ms: float, interval_s: float, bits: int) -> ReceiverReport:
    """A report at `now_ms` of one packet of `bits` over `interval_s` that met no queue."""
    delivery = DeliveryReport(
        start_ms=now_ms - interval_s * 1000.0, end_ms=now_ms, packets=1, received_bits=bits,
        lost=0, train_bits=0, train_ms=0.0, queue_delay_ms=(0.0,),
        records=(PacketRecord(0, now_ms - 30.0, now_ms - 10.0, bits),),
    )  # fmt: skip
    return ReceiverReport(now_ms / 1000.0, interval_s, bits, 1, 0, 0, 20.0, delivery=delivery)


def test_off_by_default():
    assert EngineConfig().floor_silence_skip is False
    assert _engine(False).rate.floor_silence_skip is False


@pytest.mark.parametrize(("skip", "interval_s", "skips"), [
    (True, 1.0, True), (False, 1.0, False), (True, 0.1, False), (False, 0.1, False),
])  # fmt: skip
def test_a_silent_pause_skips_the_floor_too(skip, interval_s, skips):
    """One 800-bit packet, reported at 1.0 s, none since: at 1.3 s the controller is paused
    (no report for its 150 ms). Over a 1-s report that is 0.8 kbit/s arrived, 800 bits in the
    1-s skip limit, below the floor frame's 3.2 kbit: silent, so with the key the floor's frame
    is skipped. Over a 0.1-s report it is 8 kbit/s, 8 kbit in 1 s: a trickle, not silence, so
    the floor's frame is coded with the key as without it."""
    engine = _engine(skip)
    engine.on_report(_report(1000.0, interval_s, 800), 1.0)
    assert engine.rate.paused(1.3)
    assert engine.rate.state.received_kbps == pytest.approx(0.8 / interval_s)
    assert engine.rate.skips_frame(POINTS[0], 0, 1.3, 0) is skips


def test_no_pause_no_skip_and_higher_rungs_as_before():
    """Before the pause (1.1 s: 100 ms after the report) the floor's frame is coded even over a
    silent second; a higher rung's frame is skipped in the pause with or without the key."""
    engine = _engine(True)
    engine.on_report(_report(1000.0, 1.0, 800), 1.0)
    assert not engine.rate.paused(1.1)
    assert engine.rate.skips_frame(POINTS[0], 0, 1.1, 0) is False
    for skip in (True, False):
        other = _engine(skip)
        other.on_report(_report(1000.0, 1.0, 800), 1.0)
        assert other.rate.skips_frame(POINTS[1], 0, 1.3, 0) is True


def test_without_the_floor_or_for_gcc_the_key_changes_nothing():
    """Without `rung_floor` the lowest rung is skipped by the skip rule as before; gcc never
    skips."""
    engine = _engine(True, floor=False)
    engine.on_report(_report(1000.0, 1.0, 800), 1.0)
    assert engine.rate.skips_frame(POINTS[0], 0, 1.3, 0) is True
    gcc = _engine(True, kind="gcc")
    gcc.on_report(_report(1000.0, 1.0, 800), 1.0)
    assert gcc.rate.skips_frame(POINTS[0], 0, 1.3, 0) is False
