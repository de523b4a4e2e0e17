"""The rate controller wired into the engine: bursty delivery, a handover, an application-limited
stream (its probes leave), the skip rule, the GCC baseline by name."""

from __future__ import annotations

import pytest

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.config.engine import PacerConfig
from uma.control import DeliverySettings, DeliveryTracker
from uma.engine import OutgoingUnit, ReceiverReport, SendPacket, UmaEngine
from uma.engine.decisions import CodedReport
from uma.engine.points import OperatingPoint

RATES = (30.0, 100.0, 300.0, 600.0, 1000.0, 2000.0)


def make_engine(kind: str = "uma", rates=RATES, **engine_kw) -> UmaEngine:
    config = EngineConfig(
        estimator=EstimatorConfig(initial_kbps=300.0, kind=kind),
        pacer=PacerConfig(enabled=False),  # packets leave as the engine returns them
        **engine_kw,
    )
    points = tuple(OperatingPoint("h264", r, 25.0, 176, 144, compute_ms=4.0) for r in rates)
    return UmaEngine(config, points=points, source_fps=25.0, feedback=FeedbackConfig())


class Link:
    """A FIFO bottleneck at `capacity_kbps(t_s)`, 20 ms one way; with `slot_s`, a cellular
    scheduler that delivers what the slot's capacity carried in one clump at its end."""

    def __init__(self, capacity_kbps, *, slot_s: float = 0.0) -> None:
        self.capacity_kbps, self.slot_s = capacity_kbps, slot_s
        self.free_s = 0.0
        self.tracker = DeliveryTracker(DeliverySettings(interval_ms=1e9))
        self.highest_seq = -1
        self.bits = self.packets = 0
        self.slot, self.clump = -1, 0
        self.pending: list[tuple[float, int, float, int]] = []  # sent, not yet arrived

    def send(self, packets: list[SendPacket], now_s: float) -> None:
        for packet in packets:
            self.free_s = max(self.free_s, now_s) + packet.size_bits / 1000.0 / self.capacity_kbps(
                now_s
            )
            done_s = self.free_s
            if self.slot_s:  # released at the slot's end, at 4 x the mean rate
                slot = int(done_s / self.slot_s) + 1
                self.clump = self.clump + packet.size_bits if slot == self.slot else 0
                self.slot = slot
                done_s = slot * self.slot_s + self.clump / 4000.0 / self.capacity_kbps(now_s)
            arrival_s = done_s + 0.02
            self.pending.append((arrival_s * 1000.0, packet.seq, now_s * 1000.0, packet.size_bits))
            self.bits += packet.size_bits
            self.packets += 1

    def report(self, now_s: float, technology: str = "") -> ReceiverReport:
        now_ms = now_s * 1000.0
        arrived = sorted(p for p in self.pending if p[0] <= now_ms)
        self.pending = [p for p in self.pending if p[0] > now_ms]
        for arrival_ms, seq, send_ms, size_bits in arrived:
            self.tracker.on_packet(seq, send_ms, arrival_ms, size_bits)
            self.highest_seq = max(self.highest_seq, seq)  # what arrived, not what was sent
        delivery = self.tracker.flush(now_ms)
        report = ReceiverReport(
            now_s, 0.1, delivery.received_bits, delivery.packets, delivery.lost,
            self.highest_seq, 0.0, technology=technology, delivery=delivery,
        )  # fmt: skip
        return report


def run(engine: UmaEngine, link: Link, seconds: float, *, technology=lambda t: "",
        app_max_kbps: float = 1e9) -> dict:  # fmt: skip
    """Drive the engine over `link` (reports every 100 ms, 20 ms back); per-frame estimates,
    the probes sent and the frames skipped."""
    out = {"estimate": [], "probes": 0, "skipped": 0}
    for tick in range(int(seconds * 50)):  # 20 ms ticks: a frame every two
        now_s = tick / 50.0
        if tick % 5 == 1:  # a report every 100 ms, 20 ms on the way
            report = link.report(now_s - 0.02, technology(now_s))
            actions = engine.on_report(report, now_s)
            probe = [a for a in actions if isinstance(a, SendPacket)]
            out["probes"] += bool(probe)
            link.send(probe, now_s)
        if tick % 2:
            continue
        f = tick // 2
        decision = engine.on_frame(f, now_s)
        out["estimate"].append(engine.estimate_kbps)
        out["skipped"] += decision.reason == "skip"
        if not decision.send:
            continue
        engine.on_coded(CodedReport(f, decision.rung, decision.keyframe), now_s)
        size_bytes = int(min(decision.point.rate_kbps, app_max_kbps) * 1000 / 25 / 8)
        unit = OutgoingUnit(None, size_bytes, decision.rung, (f,), decision.keyframe)
        link.send([a for a in engine.on_sent(unit, now_s) if isinstance(a, SendPacket)], now_s)
    return out


@pytest.mark.parametrize("capacity", [100.0, 250.0])
def test_bursty_delivery_reads_as_capacity_not_as_a_queue(capacity):
    """A scheduler that delivers in 40 ms clumps (at 4 x the mean rate within one) on a link
    the ladder fills: the estimate settles near the capacity, neither collapsing nor running
    away. (Where the stream does not fill the link, a frame's clump measures the burst rate:
    docs/rate-control.md gives what that costs.)"""
    engine = make_engine()
    out = run(engine, Link(lambda t: capacity, slot_s=0.04), 20.0)
    settled = sorted(out["estimate"][-250:])[125]
    assert 0.6 * capacity <= settled <= 1.05 * capacity


def test_a_handover_takes_the_technology_prior_at_once():
    engine = make_engine()
    link = Link(lambda t: 2000.0 if t < 5.0 else 40.0)
    out = run(engine, link, 6.0, technology=lambda t: "3G" if t < 5.0 else "GPRS")
    assert max(out["estimate"][100:120]) > 300.0  # 3G measured
    handover = [e for e in engine.events if e.kind == "handover_prior"]
    assert len(handover) == 1 and handover[0].detail.startswith("GPRS")
    after = out["estimate"][int(handover[0].time_s * 25) + 1]
    assert after <= 0.85 * 40.0 + 1e-9  # the GPRS prior, 40 kbit/s, at once


def test_an_application_limited_stream_probes_and_its_estimate_leaves_the_floor():
    """The stream sends 40 kbit/s on a 1,000 kbit/s link: frames are one packet (no trains),
    so only the probes measure the link; the estimate climbs well above what is sent."""
    engine = make_engine()
    out = run(engine, Link(lambda t: 1000.0), 20.0, app_max_kbps=40.0)
    assert out["probes"] >= 10
    assert engine.counts["probes"] == out["probes"]
    assert sorted(out["estimate"][-100:])[50] >= 400.0


def test_probe_packets_leave_back_to_back_numbered_as_padding():
    engine = make_engine()
    link = Link(lambda t: 1000.0)
    actions = engine.on_report(link.report(1.5), 1.5)  # nothing arrived: unmeasured
    probe = [a for a in actions if isinstance(a, SendPacket)]
    assert len(probe) == 5 and {p.kind for p in probe} == {"padding"}
    assert [p.seq for p in probe] == list(range(probe[0].seq, probe[0].seq + 5))


def test_a_queue_past_the_budget_skips_frames_but_never_for_a_second_in_a_row():
    engine = make_engine(policy="fixed", fixed_rung=5, max_backlog_ms=1e6)
    link = Link(lambda t: 300.0)
    out = run(engine, link, 6.0)
    assert out["skipped"] > 0 and engine.counts["skipped_frames"] == out["skipped"]
    # 2,000 kbit/s frames into a 300 kbit/s link: the rule lets one through at least each second
    assert out["skipped"] <= 6.0 * 25 * 0.97


def test_gcc_is_a_kind_of_its_own_and_probes_at_start():
    engine = make_engine("gcc")
    out = run(engine, Link(lambda t: 800.0), 10.0)
    assert out["probes"] >= 2  # GCC's two start-up clusters
    # It finds the link (at least 0.75 of it); the ladder's 600-kbit/s rung leaves the link
    # part idle, so an increase stops at 1.5 x what arrived + 10 (the draft's bound), and no
    # more than 800 kbit/s can arrive.
    assert 0.75 * 800.0 <= sorted(out["estimate"][-50:])[25] <= 1.5 * 800.0 + 10.0


def test_no_report_for_one_and_a_half_intervals_pauses_the_stream_until_one_comes():
    """A handover's gap or an outage: after 150 ms without a report no frame is coded (the
    estimate untouched), and the next report lets frames go again."""
    engine = make_engine()
    link = Link(lambda t: 1000.0)
    engine.on_report(link.report(0.08), 0.1)
    assert engine.on_frame(5, 0.2).send  # 100 ms: a report may be on its way
    before = engine.estimate_kbps
    paused = engine.on_frame(7, 0.28)  # 180 ms
    assert not paused.send and paused.reason == "skip"
    assert engine.estimate_kbps == before
    engine.on_report(link.report(0.28), 0.3)
    assert engine.on_frame(8, 0.32).send


def test_reports_that_come_empty_while_the_link_owes_a_frame_pause_the_stream():
    """The link stops (an outage of the downlink alone) while reports keep coming: the frame
    sent at 0.12 s is due by about 0.2 s; the report at 0.3 s holds nothing, so no frame is
    coded after it, where the same empty report with nothing outstanding changes nothing."""
    for dead in (True, False):
        engine = make_engine()
        link = Link(lambda t: 1000.0)
        run(engine, link, 0.12)  # frames 0-5 delivered and reported
        decision = engine.on_frame(6, 0.12)
        engine.on_coded(CodedReport(6, decision.rung, decision.keyframe), 0.12)
        unit = OutgoingUnit(None, 1000, decision.rung, (6,), decision.keyframe)
        packets = [a for a in engine.on_sent(unit, 0.12) if isinstance(a, SendPacket)]
        if not dead:
            link.send(packets, 0.12)
        engine.on_report(link.report(0.2), 0.22)  # the frame may still be on its way
        assert engine.on_frame(7, 0.24).send
        engine.on_report(link.report(0.3), 0.32)
        assert engine.on_frame(8, 0.32).send is not dead


@pytest.mark.parametrize("kind", ["uma", "gcc", "webrtc"])
def test_each_kind_bounds_its_own_target_and_the_engine_follows_it_as_it_is(kind):
    """`engine.estimator.max_kbps` 200 on a 1,000 kbit/s link: every kind's estimate climbs to
    the bound and never past it (the controllers bound their targets, aiortc's REMB is bounded
    where the engine takes it; `RateControl._follow` bounds nothing twice)."""
    config = EngineConfig(
        estimator=EstimatorConfig(initial_kbps=100.0, max_kbps=200.0, kind=kind),
        pacer=PacerConfig(enabled=False),
    )
    points = tuple(OperatingPoint("h264", r, 25.0, 176, 144, compute_ms=4.0) for r in RATES)
    engine = UmaEngine(config, points=points, source_fps=25.0, feedback=FeedbackConfig())
    out = run(engine, Link(lambda t: 1000.0), 15.0)
    assert max(out["estimate"]) == pytest.approx(200.0)
    if kind != "webrtc":
        assert engine.estimate_kbps == engine.rate.controller.target_kbps
