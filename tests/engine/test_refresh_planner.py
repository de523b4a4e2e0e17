"""The model-aided refresh's planner (`uma.engine.refresh`): when, how often, intra or not, and
when its packets leave."""

import pytest
from recorded import Recorded

from uma.config.codecs import RefreshConfig
from uma.engine.records import Tally
from uma.engine.refresh import (
    REFRESH_TRANSITIONS,
    RefreshEvent,
    RefreshOrder,
    RefreshPlanner,
    RefreshState,
)

FPS = 25.0


def planner(**config):
    plan = Recorded(RefreshPlanner(RefreshConfig(enabled=True, **config)))
    plan.keep([Tally(key, 0) for key in RefreshPlanner.COUNTS])
    return plan, plan.events, plan.counts


def frame(plan, index, *, budget_kbps=30.0, on_model=True, model_kbps=4.8):
    return plan.on_frame(
        index, index / FPS, on_model=on_model, budget_kbps=budget_kbps, model_kbps=model_kbps
    )


def packets(bits, size=4320):
    """A refresh of about `bits` as (packet, size_bits) pairs; packets are named by index."""
    count = max(1, round(bits / size))
    return [(f"p{i}", size) for i in range(count)]


def test_off_the_model_codec_and_disabled_nothing_is_ordered():
    plan, _, _ = planner()
    assert frame(plan, 0, on_model=False) is None
    assert plan.state is RefreshState.OFF
    disabled = Recorded(RefreshPlanner(RefreshConfig()))
    assert frame(disabled, 0) is None and disabled.state is RefreshState.OFF


def test_gsm_has_nothing_to_spare_so_it_stays_plain_mbc():
    plan, _, counts = planner()
    # GSM: 9.6 kbit/s, budget 0.85 x 9.6 = 8.2, less the model point's 4.8: 3.4 spare.
    assert all(frame(plan, i, budget_kbps=8.2) is None for i in range(250))
    assert counts["refreshes"] == 0 and plan.state is RefreshState.WAITING


def test_an_estimate_above_what_the_link_delivers_spares_nothing():
    plan, _, counts = planner()
    # GSM while the probe pads: the estimate reads 20 kbit/s (budget 17), 9.6 arrive.
    for i in range(250):
        order = plan.on_frame(
            i, i / FPS, on_model=True, budget_kbps=17.0, model_kbps=4.8, received_kbps=9.6
        )
        assert order is None
    assert counts["refreshes"] == 0
    assert plan.on_frame(
        250, 10.0, on_model=True, budget_kbps=17.0, model_kbps=4.8, received_kbps=30.0
    )


def test_first_refresh_is_intra_at_once_then_predicted_at_the_spare_rate():
    plan, events, counts = planner(share=0.8, interval_ms=1000, min_interval_ms=400)
    spare_kbps = 30.0 - 4.8
    first = frame(plan, 0)
    # Sized to what the share of the spare rate carries in an interval (to 500 bits).
    assert first == RefreshOrder(0, 20.0, 1.0, True)
    plan.coded(packets(17280), 0.0, intra=True)
    assert plan.state is RefreshState.SENDING and events[-1][1] == "refresh"
    assert frame(plan, 1) is None  # not while the last one is still leaving
    sent_bits, index = 0, 1
    while plan.state is RefreshState.SENDING:
        sent_bits += sum(bits for _, bits in plan.pace(index / FPS, queue_delay_ms=0.0))
        index += 1
    assert sent_bits == 17280
    # It drained at about the spare rate (one packet may overdraw the credit).
    assert index / FPS == pytest.approx(17280 / (spare_kbps * 1000.0), abs=4320 / 25200 + 0.05)
    # The next comes when its bits at the share of the spare rate would have taken as long.
    due_s = 17280 / (0.8 * spare_kbps * 1000.0)
    orders = {i: frame(plan, i) for i in range(index, 100)}
    first_next = min(i for i, order in orders.items() if order is not None)
    assert first_next / FPS == pytest.approx(due_s, abs=1.0 / FPS + 1e-9)
    assert orders[first_next] == RefreshOrder(first_next, 20.0, 1.0, False)
    assert counts["refreshes"] == 1


def test_a_stream_keeps_its_size_until_the_spare_rate_doubles_it():
    plan, _, _ = planner(min_frame_bits=4000, max_frame_bits=64000, min_interval_ms=40)

    def drain(order):
        plan.coded(packets(1000 * order.rate_kbps), order.frame / FPS, intra=order.intra)
        while plan.state is RefreshState.SENDING:
            plan.pace(plan.last_pace_s + 0.04, queue_delay_ms=0.0)

    first = frame(plan, 0, budget_kbps=14.8)  # 10 spare: 8 kbit an interval
    assert first.intra and first.rate_kbps == 8.0
    drain(first)
    sizes = []
    for i in range(1, 400):
        budget = 14.8 if i < 100 else 24.8 if i < 200 else 44.8  # 10, 20 and 40 spare
        order = frame(plan, i, budget_kbps=budget)
        if order is not None:
            sizes.append(((i >= 100) + (i >= 200), order.rate_kbps, order.intra))
            drain(order)
    # 20 spare is 16 kbit an interval, twice 8: one intra at 16, then predicted; 40: 32.
    assert (0, 8.0, False) in sizes and (1, 16.0, True) in sizes and (2, 32.0, True) in sizes
    assert [s for s in sizes if s[2]] == [(1, 16.0, True), (2, 32.0, True)]
    assert {s[1] for s in sizes if s[0] == 1} == {16.0} and len(sizes) > 10


def test_the_first_refresh_is_within_its_size_bounds():
    plan, _, _ = planner(min_frame_bits=8000, max_frame_bits=12000, min_spare_kbps=2.0)
    assert frame(plan, 0, budget_kbps=200.0).rate_kbps == 12.0
    plan, _, _ = planner(min_frame_bits=8000, max_frame_bits=12000, min_spare_kbps=2.0)
    assert frame(plan, 0, budget_kbps=4.8 + 4.0).rate_kbps == 8.0  # 8 kbit in 2.5 s


def test_a_rich_link_is_refreshed_no_faster_than_the_minimum_interval():
    plan, _, _ = planner(max_frame_bits=8000, min_interval_ms=1000)
    frame(plan, 0, budget_kbps=500.0)
    plan.coded(packets(8640), 0.0, intra=True)
    plan.pace(0.0, queue_delay_ms=0.0)
    plan.pace(0.04, queue_delay_ms=0.0)
    assert plan.state is RefreshState.WAITING
    due = [i for i in range(1, 60) if frame(plan, i, budget_kbps=500.0) is not None]
    assert due[0] == 25


def test_a_poor_link_waits_longer_than_the_maximum_interval_for_nothing():
    plan, _, _ = planner(min_frame_bits=16000, max_interval_ms=1000, min_spare_kbps=1.0)
    # 10 kbit/s spare at share 0.8: 16 kbit would take 2 s > 1 s.
    assert all(frame(plan, i, budget_kbps=14.8) is None for i in range(100))


def test_packets_hold_while_the_queue_builds_not_on_a_slower_links_delay():
    plan, _, _ = planner(queue_high_ms=100, queue_window_ms=2000)
    plan.pace(0.0, queue_delay_ms=0.0)
    frame(plan, 0)
    plan.coded(packets(17280), 0.0, intra=True)
    assert plan.pace(0.5, queue_delay_ms=150.0) == []  # 150 ms above the last 2 s' least
    assert plan.pace(0.54, queue_delay_ms=150.0) == []
    # No credit was saved up meanwhile: one packet, not a burst.
    assert len(plan.pace(0.58, queue_delay_ms=0.0)) == 1
    # A handover to GPRS: the receiver reads 290 ms more for seconds, with no queue behind it.
    held = [bool(plan.pace(t, queue_delay_ms=290.0)) for t in (0.8, 1.5, 2.2, 2.62, 2.66)]
    assert held[:2] == [False, False] and any(held[2:])


def test_while_held_no_refresh_packet_leaves_and_no_credit_is_saved():
    """The feedback has gone quiet (a handover's gap may have begun): no refresh packet goes
    out; when a report comes again the refresh goes on where it was, one packet, not a burst."""
    plan, _, _ = planner()
    frame(plan, 1)
    plan.coded(packets(4320 * 4), 1 / FPS, intra=True)
    assert plan.pace(1 / FPS, queue_delay_ms=0.0, held=True) == []
    assert all(plan.pace(i / FPS, queue_delay_ms=0.0, held=True) == [] for i in range(2, 50))
    assert len(plan.queue) == 4 and plan.state is RefreshState.SENDING
    assert len(plan.pace(50 / FPS, queue_delay_ms=0.0)) == 1


def test_leaving_the_model_codec_drops_a_half_sent_refresh_and_the_next_is_intra():
    plan, events, counts = planner()
    frame(plan, 0)
    plan.coded(packets(17280), 0.0, intra=True)
    plan.pace(0.0, queue_delay_ms=0.0)
    assert frame(plan, 1, on_model=False) is None
    assert plan.state is RefreshState.OFF and plan.queue == type(plan.queue)()
    assert counts["refresh_dropped"] == 1 and events[-1][1] == "refresh_dropped"
    order = frame(plan, 200)
    assert order is not None and order.intra


def test_a_refresh_under_way_still_leaves_when_the_spare_rate_falls():
    plan, _, counts = planner(min_spare_kbps=8.0)
    frame(plan, 0)
    plan.coded(packets(4320 * 4), 0.0, intra=True)
    plan.pace(0.0, queue_delay_ms=0.0)  # one packet now, three to go
    assert frame(plan, 1, budget_kbps=4.8) is None  # nothing spare: no new refresh
    assert plan.state is RefreshState.SENDING and counts["refresh_dropped"] == 0
    # Still at half the floor, 4 kbit/s: 4,320 bits a packet take about 1.08 s each.
    times = []
    for i in range(2, 200):
        if plan.pace(i / FPS, queue_delay_ms=0.0):
            times.append(i / FPS)
    assert len(times) == 3 and plan.state is RefreshState.WAITING
    assert times[1] - times[0] == pytest.approx(4320 / 4000.0, abs=1.5 / FPS)


def test_a_lost_refresh_makes_the_next_intra():
    plan, _, _ = planner(min_interval_ms=400)
    frame(plan, 0)
    plan.coded(packets(4320), 0.0, intra=True)
    plan.pace(0.0, queue_delay_ms=0.0)
    plan.request_intra(0.3)
    order = next(o for i in range(1, 100) if (o := frame(plan, i)) is not None)
    assert order.intra


def test_the_receivers_refresh_is_handed_on_once_and_never_backwards():
    plan, _, counts = planner()
    assert plan.take_adopted() is None
    plan.on_ack(-1)
    assert plan.take_adopted() is None
    plan.on_ack(40)
    plan.on_ack(40)
    assert plan.take_adopted() == 40 and plan.take_adopted() is None
    plan.on_ack(20)
    assert plan.take_adopted() is None and counts["refresh_adopted"] == 1


def test_released_bits_are_taken_once_for_the_probes_padding():
    plan, _, _ = planner()
    frame(plan, 0)
    plan.coded(packets(8640), 0.0, intra=True)
    plan.pace(0.0, queue_delay_ms=0.0)
    assert plan.take_released_bits() == 4320 and plan.take_released_bits() == 0


def test_every_state_can_leave_and_nothing_else_is_allowed():
    assert all((state, RefreshEvent.LEAVE) in REFRESH_TRANSITIONS for state in RefreshState)
    plan, _, _ = planner()
    with pytest.raises(RuntimeError, match="no transition from OFF on CODED"):
        plan.fire(RefreshEvent.CODED)


def test_the_spare_rate_is_capped_by_the_most_delivered_over_the_longest_interval():
    """What arrived over the last second is low between refreshes spaced more than a second
    apart (the refresh's own bits are most of it): the cap is the most any window of the
    last `max_interval_ms` delivered, so a refresh does not shrink the next one's rate; a
    window older than that no longer counts."""
    plan, _, _ = planner(max_interval_ms=3000)

    def spare(t_s, received_kbps):
        plan.on_frame(
            int(t_s * FPS), t_s, on_model=True, budget_kbps=30.0, model_kbps=4.8,
            received_kbps=received_kbps,
        )  # fmt: skip
        return plan.spare_kbps

    assert spare(0.0, 20.0) == pytest.approx(15.2)
    assert spare(1.5, 8.0) == pytest.approx(15.2)  # the window with the refresh still counts
    assert spare(2.9, 40.0) == pytest.approx(25.2)  # never above the budget
    assert spare(6.0, 8.0) == pytest.approx(3.2)  # 3 s later only the last window counts
