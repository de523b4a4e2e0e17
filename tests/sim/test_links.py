import numpy as np
import pytest
import simpy

from uma.sim.capacity import CapacitySchedule
from uma.sim.links import Downlink, FixedLink, LinkProps, downlink_process
from uma.sim.packets import EncodedUnit, Packet, packetize

UNIT = EncodedUnit(
    unit_seq=0, frame=0, codec="h264", rung=0, width=16, height=16, keyframe=True, data=b"x" * 10
)


def packet(seq, size_bits):
    return Packet(seq=seq, unit=UNIT, index=0, count=1, size_bits=size_bits, sent_s=0.0)


def run_link(capacity, offers, *, queue_bytes=10_000, delay_s=0.1, loss=0.0, until=50.0):
    """offers: list of (time_s, packet); returns {seq: arrival_s} and the link."""
    env = simpy.Environment()
    arrivals = {}
    link = Downlink(
        env=env,
        capacity=capacity,
        queue_limit_bytes=queue_bytes,
        props=lambda tech: LinkProps(delay_s, loss),
        rng=np.random.default_rng(0),
        deliver=lambda p: arrivals.__setitem__(p.seq, env.now),
    )

    def offerer():
        for when, pkt in offers:
            yield env.timeout(when - env.now)
            link.offer(pkt)

    env.process(offerer())
    env.process(downlink_process(env, link))
    env.run(until=until)
    return arrivals, link


def test_delivery_times_by_hand_with_outage_inside_a_packet():
    # 1000 bit/s, outage 1-2 s: A leaves at 1.0; B starts at 1.0, waits the outage, leaves at 3.0.
    cap = CapacitySchedule([0.0, 1.0, 2.0], [1000.0, 0.0, 1000.0])
    arrivals, _ = run_link(cap, [(0.0, packet(0, 1000)), (0.0, packet(1, 1000))])
    assert arrivals[0] == pytest.approx(1.1)
    assert arrivals[1] == pytest.approx(3.1)


def test_packet_split_by_outage():
    cap = CapacitySchedule([0.0, 1.0, 2.0], [1000.0, 0.0, 1000.0])
    arrivals, _ = run_link(cap, [(0.5, packet(0, 1000))])
    assert arrivals[0] == pytest.approx(2.5 + 0.1)


def test_idle_link_starts_when_packet_arrives():
    cap = CapacitySchedule([0.0], [8000.0])
    arrivals, _ = run_link(cap, [(2.0, packet(0, 800)), (2.05, packet(1, 800))], delay_s=0.0)
    assert arrivals[0] == pytest.approx(2.1)
    assert arrivals[1] == pytest.approx(2.2)  # waited for the first


def test_drop_tail_counts_bytes_including_packet_in_service():
    cap = CapacitySchedule([0.0], [1000.0])
    offers = [(0.0, packet(i, 1000)) for i in range(3)]  # 125 bytes each
    arrivals, link = run_link(cap, offers, queue_bytes=300)
    assert sorted(arrivals) == [0, 1]
    assert link.stats.packets_dropped_queue == 1


def test_zero_capacity_forever_holds_packets_without_error():
    cap = CapacitySchedule([0.0, 1.0], [1000.0, 0.0])
    arrivals, link = run_link(cap, [(0.0, packet(0, 800)), (0.0, packet(1, 800))])
    assert list(arrivals) == [0]
    assert len(link.queue) == 1


def test_random_loss_rate_is_respected():
    cap = CapacitySchedule([0.0], [1e6])
    offers = [(0.0, packet(i, 800)) for i in range(2000)]
    arrivals, link = run_link(cap, offers, queue_bytes=10**7, loss=0.1)
    assert 150 < link.stats.packets_lost_random < 250
    assert len(arrivals) + link.stats.packets_lost_random == 2000


def test_delivery_stays_in_order_when_delay_shrinks():
    cap = CapacitySchedule([0.0, 1.0], [1000.0, 1000.0], ["GPRS", "WLAN"])
    env = simpy.Environment()
    arrivals = []
    props = {"GPRS": LinkProps(0.5, 0.0), "WLAN": LinkProps(0.01, 0.0)}
    link = Downlink(
        env=env,
        capacity=cap,
        queue_limit_bytes=10_000,
        props=props.__getitem__,
        rng=np.random.default_rng(0),
        deliver=lambda p: arrivals.append((p.seq, env.now)),
    )
    link.offer(packet(0, 900))
    link.offer(packet(1, 200))
    env.process(downlink_process(env, link))
    env.run(until=5)
    assert [seq for seq, _ in arrivals] == [0, 1]
    assert arrivals[1][1] >= arrivals[0][1]


def test_fixed_link_serialises_fifo():
    env = simpy.Environment()
    got = []
    link = FixedLink(env, rate_bps=1000.0, delay_s=0.5)
    link.send(1000, "a", lambda item: got.append((item, env.now)))
    link.send(500, "b", lambda item: got.append((item, env.now)))
    env.run()
    assert got == [("a", pytest.approx(1.5)), ("b", pytest.approx(2.0))]


def test_packetize_covers_the_unit():
    unit = EncodedUnit(
        unit_seq=3,
        frame=7,
        codec="h264",
        rung=1,
        width=16,
        height=16,
        keyframe=False,
        data=b"y" * 2500,
    )
    packets = packetize(unit, first_seq=10, payload_bytes=1200, sent_s=1.0)
    assert [p.seq for p in packets] == [10, 11, 12]
    assert sum(p.size_bits for p in packets) == 8 * (2500 + 3 * 40)
    assert all(p.count == 3 for p in packets)
