import numpy as np

from uma.metrics.framelog import FrameLog
from uma.sim.packets import EncodedUnit, packetize
from uma.sim.receiver import ReceiverState


class Clock:
    t = 0.0

    def __call__(self):
        return self.t


def make_receiver():
    clock = Clock()
    requests = []
    decoded_units = []

    def decode(unit):
        decoded_units.append(unit.unit_seq)
        return {unit.frame: np.full((24, 16), unit.frame, dtype=np.uint8)}

    receiver = ReceiverState(
        log=FrameLog(20), decode=decode, request_keyframe=requests.append, now=clock
    )
    return receiver, clock, requests, decoded_units


def unit(seq, frame, *, key=False, size=2000):
    return EncodedUnit(
        unit_seq=seq,
        frame=frame,
        codec="h264",
        rung=0,
        width=16,
        height=16,
        keyframe=key,
        data=b"z" * size,
    )


def deliver(receiver, clock, u, first_seq, t, *, drop=()):
    clock.t = t
    packets = packetize(u, first_seq=first_seq, payload_bytes=1000, sent_s=t - 0.05)
    for p in packets:
        if p.index not in drop:
            receiver.on_packet(p)
    return first_seq + len(packets)


def test_complete_chain_decodes_every_frame():
    receiver, clock, requests, decoded = make_receiver()
    seq = 0
    for i in range(4):
        seq = deliver(receiver, clock, unit(i, 2 * i, key=i == 0), seq, 0.1 * i)
    assert decoded == [0, 1, 2, 3]
    assert requests == []
    assert receiver.log["decoded"][[0, 2, 4, 6]].tolist() == [1, 1, 1, 1]
    assert receiver.log["arrival_ms"][2] == 100.0


def test_lost_packet_breaks_chain_until_idr_and_asks_for_one():
    receiver, clock, requests, decoded = make_receiver()
    seq = deliver(receiver, clock, unit(0, 0, key=True), 0, 0.0)
    seq = deliver(receiver, clock, unit(1, 1), seq, 0.04, drop={1})  # incomplete
    seq = deliver(receiver, clock, unit(2, 2), seq, 0.08)  # reveals the loss; not decodable
    seq = deliver(receiver, clock, unit(3, 3), seq, 0.12)
    assert decoded == [0]
    assert len(requests) == 1
    seq = deliver(receiver, clock, unit(4, 4, key=True), seq, 0.16)
    seq = deliver(receiver, clock, unit(5, 5), seq, 0.20)
    assert decoded == [0, 4, 5]


def test_wholly_lost_unit_is_noticed_by_its_successor():
    receiver, clock, requests, decoded = make_receiver()
    seq = deliver(receiver, clock, unit(0, 0, key=True), 0, 0.0)
    seq += 2  # unit 1 dropped entirely at the queue
    deliver(receiver, clock, unit(2, 2), seq, 0.1)
    assert decoded == [0]
    report = receiver.make_report(0.1)
    assert report.packets_lost == 2
    assert len(requests) == 1


def test_shown_frame_is_newest_not_newer_than_display_slot():
    receiver, clock, _, _ = make_receiver()
    seq = deliver(receiver, clock, unit(0, 0, key=True), 0, 0.0)
    seq = deliver(receiver, clock, unit(1, 3), seq, 0.1)
    seq = deliver(receiver, clock, unit(2, 5), seq, 0.2)
    from uma.sim.playout_replay import newest_decoded

    assert newest_decoded(receiver.decoded, 2) == 0
    assert newest_decoded(receiver.decoded, 4) == 3
    shown = newest_decoded(receiver.decoded, 9)
    assert shown == 5 and receiver.decoded[shown][0, 0] == 5
    assert sorted(receiver.decoded) == [5]  # older pictures are let go


def test_report_measures_rate_and_queue_delay():
    receiver, clock, _, _ = make_receiver()
    seq = deliver(receiver, clock, unit(0, 0, key=True, size=1000), 0, 1.0)
    report = receiver.make_report(0.5)
    assert report.received_bits == 8 * (1000 + 40)
    assert report.received_kbps == 8 * 1040 / 0.5 / 1000
    assert report.queue_delay_ms == 0.0
    assert report.highest_seq == seq - 1
    empty = receiver.make_report(0.5)
    assert empty.packets_received == 0 and empty.queue_delay_ms is None


def test_padding_packets_are_counted_but_not_assembled():
    from uma.sim.packets import padding_packets, padding_sizes_bits
    from uma.sim.receiver import ReceiverState

    log = FrameLog(4)
    now = [1.0]
    receiver = ReceiverState(
        log=log, decode=lambda unit: {}, request_keyframe=lambda r: None, now=lambda: now[0]
    )
    sizes = padding_sizes_bits(8 * 3000, payload_bytes=1200)
    assert sum(sizes) == 8 * 3000 and max(sizes) == 8 * 1240
    for packet in padding_packets(sizes, first_seq=0, sent_s=0.9):
        receiver.on_packet(packet)
    report = receiver.make_report(0.1)
    assert report.packets_received == len(sizes) and report.received_bits == 8 * 3000
    assert report.packets_lost == 0 and not receiver.assembling
    assert padding_sizes_bits(8 * 30, payload_bytes=1200) == []  # not even a header's worth


def test_reports_carry_the_access_technology_the_receiver_is_on():
    now = [0.0]
    on = ["3G"]
    receiver = ReceiverState(
        log=FrameLog(4), decode=lambda unit: {}, request_keyframe=lambda r: None,
        now=lambda: now[0], technology=lambda: on[0],
    )  # fmt: skip
    assert receiver.make_report(0.1).technology == "3G"
    on[0] = "GPRS"
    assert receiver.make_report(0.1).technology == "GPRS"
    silent = ReceiverState(
        log=FrameLog(4), decode=lambda unit: {}, request_keyframe=lambda r: None,
        now=lambda: now[0],
    )  # fmt: skip
    assert silent.make_report(0.1).technology == ""


def test_reports_carry_what_arrived_and_a_new_path_is_measured_afresh():
    """Each report carries the tracker's `DeliveryReport` of the interval (every packet, its
    send stamp and arrival); a change of technology forgets the path's propagation delay, and
    once more `PATH_SETTLE_S` later."""
    from uma.control import DeliverySettings, DeliveryTracker
    from uma.sim.packets import Packet
    from uma.sim.receiver import PATH_SETTLE_S

    receiver, clock, _, _ = make_receiver()
    receiver.delivery = DeliveryTracker(DeliverySettings(interval_ms=1e9))
    technology = ["3G"]
    receiver.technology = lambda: technology[0]

    def arrive(seq, sent_s, t):
        clock.t = t
        receiver.on_packet(Packet(seq, None, 0, 1, 8000, sent_s))

    arrive(0, 0.00, 0.02)  # 20 ms one way: the base
    arrive(1, 0.05, 0.07)
    report = receiver.make_report(0.1)
    assert report.delivery.packets == 2 and report.delivery.received_bits == 16000
    assert [r.seq for r in report.delivery.records] == [0, 1]
    assert report.delivery.queue_delay_ms == (0.0, 0.0)
    arrive(2, 0.10, 0.45)  # 350 ms one way: a slower path...
    technology[0] = "GPRS"
    clock.t = 0.5
    assert receiver.make_report(0.1).delivery.queue_delay_ms == (330.0,)  # ...read as queue
    arrive(3, 0.55, 0.90)  # after the change: the new path's delay is its base
    assert receiver.make_report(0.1).delivery.queue_delay_ms == (0.0,)
    assert receiver.settle_at_s == 0.5 + PATH_SETTLE_S
