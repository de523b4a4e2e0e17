"""`engine.estimator`'s switches for uma's controller reach its settings (off by default, but
the adopted ones), and the skip limit's switch acts through the engine's public calls."""

from __future__ import annotations

import pytest

from uma.config.engine import EstimatorConfig
from uma.config.scenario import EngineConfig, FeedbackConfig
from uma.engine.rate import make_rate

KEYS = (
    "recover_after_silence",
    "overdue_in_any_report",
    "no_probe_while_owed",
    "no_probe_into_silence",
    "take_queued_drop",
    "bounded_queued_drop",
    "judge_silence",
)
ON_KEYS = (  # adopted (docs/rate-control.md, rc14, rc15; docs/measured.md, section 19)
    "fixed_due_time",
    "no_probe_while_paused",
    "skip_limit_by_received",
    "queue_from_owed",
)


@pytest.mark.parametrize("key", KEYS)
def test_an_estimator_switch_reaches_uma_s_controller_and_is_off_by_default(key):
    default = make_rate(EngineConfig(estimator=EstimatorConfig()), FeedbackConfig())
    assert getattr(default.controller.settings, key) is False
    on = make_rate(EngineConfig(estimator=EstimatorConfig(**{key: True})), FeedbackConfig())
    assert getattr(on.controller.settings, key) is True
    others = [k for k in KEYS if k != key]
    assert not any(getattr(on.controller.settings, k) for k in others)


@pytest.mark.parametrize("key", ON_KEYS)
def test_an_adopted_estimator_switch_is_on_by_default_and_can_be_turned_off(key):
    default = make_rate(EngineConfig(estimator=EstimatorConfig()), FeedbackConfig())
    assert getattr(default.controller.settings, key) is True
    off = make_rate(EngineConfig(estimator=EstimatorConfig(**{key: False})), FeedbackConfig())
    assert getattr(off.controller.settings, key) is False


def _skipped_after_a_report(on: bool, received_kbps: float) -> int:
    """Frames of 10 kbit asked every 40 ms for 2 s after the last report (the sender paused
    from 150 ms after it), that report counting `received_kbps` over one second: how many
    were not sent."""
    from uma.control.delivery import DeliveryReport, PacketRecord
    from uma.engine.reports import ReceiverReport

    estimator = EstimatorConfig(skip_limit_by_received=on)
    rate = make_rate(EngineConfig(estimator=estimator), FeedbackConfig())
    bits = int(received_kbps * 1000.0)
    delivery = DeliveryReport(
        start_ms=0.0, end_ms=1000.0, packets=1, received_bits=bits, lost=0, train_bits=0,
        train_ms=0.0, queue_delay_ms=(0.0,), records=(PacketRecord(0, 950.0, 970.0, bits),),
    )  # fmt: skip
    rate.on_report(ReceiverReport(1.0, 1.0, bits, 1, 0, 0, 0.0, delivery=delivery), 1.0)
    assert rate.state.received_kbps == pytest.approx(received_kbps)
    times_s = [1.2 + 0.04 * k for k in range(50)]
    return sum(rate.skip(10_000.0, 0.0, now_s) for now_s in times_s)


@pytest.mark.parametrize(
    ("on", "received_kbps", "sent"), [(False, 2.0, 1), (True, 2.0, 0), (True, 20.0, 1)]
)
def test_past_the_skip_limit_a_silent_link_gets_no_frame_and_a_trickle_does(
    on, received_kbps, sent
):
    """Paused for 2 s: the 1-s limit sends a frame after a second of skips; with
    `skip_limit_by_received` only if its 10 kbit drain within that second at what arrived
    (20 kbit/s, not 2)."""
    assert 50 - _skipped_after_a_report(on, received_kbps) == sent


@pytest.mark.parametrize(("owed", "sent_after_bits", "queue_ms"), [
    (False, 0, 900.0), (True, 0, 0.0), (True, 48_000, 160.0), (True, None, 900.0),
])  # fmt: skip
def test_the_queue_is_read_from_what_the_engine_s_record_still_owes(
    owed, sent_after_bits, queue_ms
):
    """A report of a packet (seq 0) that met 900 ms of queue, the estimate 300 kbit/s: with
    `queue_from_owed` the controller's queue is at most the bits sent after it at that rate
    (48,000 bits: 160 ms; none: 0); without the key, or with no in-flight record, the 900."""
    from uma.control.delivery import DeliveryReport, PacketRecord
    from uma.engine.inflight import InFlight
    from uma.engine.reports import ReceiverReport

    rate = make_rate(
        EngineConfig(estimator=EstimatorConfig(queue_from_owed=owed)), FeedbackConfig()
    )
    inflight = InFlight()
    inflight.on_sent([9600], 0.0)
    if sent_after_bits:
        inflight.on_sent([sent_after_bits], 0.9)
    inflight.on_report(0, 1.0)
    delivery = DeliveryReport(
        start_ms=900.0, end_ms=1000.0, packets=1, received_bits=9600, lost=0, train_bits=0,
        train_ms=0.0, queue_delay_ms=(900.0,), records=(PacketRecord(0, 0.0, 950.0, 9600),),
    )  # fmt: skip
    report = ReceiverReport(1.0, 0.1, 9600, 1, 0, 0, 900.0, delivery=delivery)
    rate.on_report(report, 1.0, None if sent_after_bits is None else inflight)
    assert rate.controller.capacity_kbps == pytest.approx(300.0)
    assert rate.controller.queue_ms == pytest.approx(queue_ms)
