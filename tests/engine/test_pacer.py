"""The engine's pacer on scripted traces: its rate, burst, late drops and priorities."""

from __future__ import annotations

from uma.engine.pacer import PADDING, PRIORITY, VIDEO, PacedPacket, Pacer

PACKET_BITS = 8 * 1240


def _unit(unit: int, frame: int, deadline_s: float, *, packets: int = 1, keyframe=False):
    return [
        PacedPacket((unit, i), PACKET_BITS, unit, frame, deadline_s, keyframe)
        for i in range(packets)
    ]


def _drain(pacer: Pacer, rate_kbps: float, until_s: float, *, delay_s: float = 0.0):
    """Run the pacer as the world does; (time_s, payload) of everything sent, frames dropped."""
    now_s, sent, dropped = 0.0, [], []
    while now_s <= until_s:
        release = pacer.release(now_s, rate_kbps, network_delay_s=delay_s)
        sent += [(now_s, packet.payload) for packet in release.sent]
        dropped += release.dropped_frames
        if release.next_s == float("inf"):
            break
        now_s = release.next_s
    return sent, dropped


def test_packets_leave_at_the_rate_given():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    pacer.push(_unit(0, 0, 100.0, packets=50, keyframe=True), VIDEO)
    sent, dropped = _drain(pacer, 496.0, 10.0)  # 496 kbit/s: 20 ms a packet
    assert len(sent) == 50 and not dropped
    span_s = sent[-1][0] - sent[0][0]
    assert abs(span_s - 49 * PACKET_BITS / 496e3) <= 0.05  # less the burst at the start
    assert pacer.queued_bits == 0


def test_a_step_down_makes_the_queue_build_here_and_late_frames_drop():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    # 25 frames/s of 4 packets (about 1 Mbit/s) into a pacer allowed 200 kbit/s.
    for frame in range(25):
        pacer.push(_unit(frame, frame, frame / 25 + 0.5, packets=4, keyframe=frame == 0), VIDEO)
    release = pacer.release(0.0, 200.0, network_delay_s=0.0)
    assert pacer.queued_bits > 0
    sent, dropped = _drain(pacer, 200.0, 5.0)
    assert dropped, "frames that can no longer be shown in time are dropped"
    units_sent = {payload[0] for _, payload in sent} | {p.unit for p in release.sent}
    assert units_sent.isdisjoint(set(dropped))
    # Nothing left the pacer too late for its deadline.
    for time_s, (unit, _) in sent:
        assert time_s <= unit / 25 + 0.5 + 0.05


def test_a_drop_takes_its_dependants_and_asks_for_a_keyframe():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    pacer.push(_unit(0, 0, 0.1, packets=10), VIDEO)
    pacer.push(_unit(1, 1, 5.0), VIDEO)
    release = pacer.release(0.0, 100.0, network_delay_s=0.0)
    assert release.dropped_frames == (0, 1) and release.needs_keyframe
    pacer.push(_unit(2, 2, 0.1, packets=10), VIDEO)
    pacer.push(_unit(3, 3, 0.1, packets=10), VIDEO)
    pacer.push(_unit(4, 4, 5.0), VIDEO)
    # A keyframe queued behind them supersedes them at once.
    assert pacer.push(_unit(5, 5, 0.1, packets=10, keyframe=True), VIDEO) == (2, 3, 4)
    release = pacer.release(0.0, 100.0, network_delay_s=0.0)
    assert release.dropped_frames == () and not release.needs_keyframe


def test_a_keyframe_is_never_dropped_late_only_superseded():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    pacer.push(_unit(0, 0, 0.1, packets=10, keyframe=True), VIDEO)
    assert pacer.release(0.0, 50.0, network_delay_s=1.0).dropped_frames == ()
    pacer.push(_unit(1, 1, 0.2), VIDEO)
    assert pacer.push(_unit(2, 2, 0.3, keyframe=True), VIDEO) == (1,)  # unit 0 has started
    sent, dropped = _drain(pacer, 50.0, 10.0, delay_s=1.0)
    assert {payload[0] for _, payload in sent} == {0, 2} and dropped == []


def test_reported_queueing_delay_counts_against_the_deadline():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    pacer.push(_unit(0, 0, 0.5), VIDEO)
    assert pacer.release(0.0, 1000.0, network_delay_s=0.2).dropped_frames == ()
    pacer.push(_unit(1, 1, 0.5), VIDEO)
    assert pacer.release(0.1, 1000.0, network_delay_s=0.6).dropped_frames == (1,)


def test_model_parameters_go_first_and_displace_waiting_full_frame_units():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    pacer.push(_unit(0, 0, 100.0, packets=3), VIDEO)
    first = pacer.release(0.0, 200.0, network_delay_s=0.0)
    assert [p.unit for p in first.sent] == [0]  # one packet of unit 0 left: it finishes
    pacer.push(_unit(1, 1, 100.0, packets=2), VIDEO)
    dropped = pacer.push(_unit(2, 2, 100.0), PRIORITY)
    assert dropped == (1,)
    sent, _ = _drain(pacer, 200.0, 5.0)
    assert [payload for _, payload in sent] == [(0, 1), (0, 2), (2, 0)]


def test_padding_is_last_and_goes_stale():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    pacer.push([PacedPacket("pad", PACKET_BITS, -1, -1, 0.0)], PADDING)
    pacer.push(_unit(0, 0, 100.0, packets=3), VIDEO)
    release = pacer.release(0.0, 100.0, network_delay_s=0.0)
    assert [p.payload for p in release.sent] == [(0, 0)]
    sent, _ = _drain(pacer, 100.0, 5.0)
    assert "pad" not in [payload for _, payload in sent]
    assert pacer.queued_bits == 0


def test_burst_allowance_bounds_what_leaves_at_once():
    pacer = Pacer(burst_ms=100.0, padding_wait_ms=100.0)
    pacer.release(0.0, 992.0, network_delay_s=0.0)  # idle: the bucket fills to its burst
    pacer.push(_unit(0, 0, 100.0, packets=40), VIDEO)
    release = pacer.release(10.0, 992.0, network_delay_s=0.0)
    # 100 ms at 992 kbit/s is 99.2 kbit: ten 9.92 kbit packets and no more than one over.
    assert 10 <= len(release.sent) <= 11


def test_a_silent_feedback_path_holds_everything_and_judges_deadlines_still():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    pacer.push(_unit(0, 0, 0.5, packets=2), VIDEO)
    held = pacer.release(0.0, 1000.0, network_delay_s=0.0, hold=True)
    assert held.sent == () and held.next_s == float("inf") and pacer.queued_bits > 0
    assert pacer.release(0.3, 1000.0, network_delay_s=0.0, hold=True).sent == ()
    assert pacer.release(0.6, 1000.0, network_delay_s=0.0, hold=True).dropped_frames == (0,)
    pacer.push(_unit(1, 1, 5.0, keyframe=True), VIDEO)
    assert len(pacer.release(0.7, 1000.0, network_delay_s=0.0).sent) == 1


def test_a_late_keyframe_is_dropped_while_the_pacer_holds():
    pacer = Pacer(burst_ms=40.0, padding_wait_ms=100.0)
    pacer.push(_unit(0, 0, 0.5, packets=2, keyframe=True), VIDEO)
    assert pacer.release(0.0, 1000.0, network_delay_s=0.0, hold=True).dropped_frames == ()
    release = pacer.release(0.6, 1000.0, network_delay_s=0.0, hold=True)
    assert release.dropped_frames == (0,) and release.needs_keyframe
