"""How a refresh's packets leave (`engine.mbc.refresh.release`: paced or in one burst after a
report) and the refresh's quiet after a handover that found refresh bits in its gap
(`handover_quiet`), on hand-worked event sequences (`uma.engine.refresh.RefreshPlanner`)."""

import pytest

from uma.config.codecs import RefreshConfig
from uma.engine.records import EngineEvent, Tally
from uma.engine.refresh import RefreshEvent, RefreshPlanner, RefreshState
from uma.engine.reports import ReceiverReport

FPS = 25.0
PACKETS = [(f"p{i}", 4320) for i in range(4)]  # a refresh of four 540-byte packets


def sending(**config) -> RefreshPlanner:
    """A planner with a predicted stream under way at 23.2 kbit/s spare."""
    plan = RefreshPlanner(RefreshConfig(enabled=True, min_spare_kbps=4.0, **config))
    plan.fire(RefreshEvent.ENTER)
    plan.spare_kbps, plan.intra_due = 23.2, False
    return plan


def report(sent_s: float, technology: str = "GPRS") -> ReceiverReport:
    return ReceiverReport(sent_s, 0.1, 0, 0, 0, -1, 0.0, technology=technology)


def test_a_burst_leaves_whole_at_the_first_frame_after_a_report():
    """Coded at 0.92 s; reports arrive at 0.95 and 1.05 s (sent 0.35 s before). Frames at
    0.92 and 0.96: no report since the refresh was coded at 0.92, then the 0.95-s one: all
    four packets leave at 0.96, none before, and the stream waits for its next order."""
    plan = sending(release="burst")
    plan.coded(PACKETS, 0.92, intra=False)
    assert plan.pace(0.92, queue_delay_ms=0.0) == []
    plan.on_report(report(0.60), 0.95, 30.0, False)
    assert plan.pace(0.96, queue_delay_ms=0.0) == PACKETS
    assert plan.state is RefreshState.WAITING and not plan.queue
    assert plan.take_released_bits() == 4 * 4320


def test_a_report_seen_before_the_refresh_was_coded_does_not_release_it():
    """The frame's `pace` reads a report once: one that arrived before the coding was used up
    by the frame before, so the burst waits for the next report."""
    plan = sending(release="burst")
    plan.on_report(report(0.55), 0.90, 30.0, False)
    assert plan.pace(0.90, queue_delay_ms=0.0) == []  # nothing to send yet
    plan.coded(PACKETS, 0.92, intra=False)
    assert plan.pace(0.92, queue_delay_ms=0.0) == []
    assert plan.pace(0.96, queue_delay_ms=0.0) == []
    plan.on_report(report(0.65), 1.00, 30.0, False)
    assert len(plan.pace(1.00, queue_delay_ms=0.0)) == 4


def test_a_burst_waits_while_held_or_while_the_queue_builds():
    """Late reports (`held`) or a queue 150 ms above the window's least: the burst waits for
    a report after they clear; the paced release would have sent one packet at once."""
    plan = sending(release="burst")
    plan.pace(0.0, queue_delay_ms=0.0)
    plan.coded(PACKETS, 0.92, intra=False)
    plan.on_report(report(0.60), 0.95, 30.0, False)
    assert plan.pace(0.96, queue_delay_ms=0.0, held=True) == []
    plan.on_report(report(0.70), 1.05, 30.0, False)
    assert plan.pace(1.08, queue_delay_ms=150.0) == []
    plan.on_report(report(0.80), 1.15, 30.0, False)
    assert len(plan.pace(1.16, queue_delay_ms=0.0)) == 4
    paced = sending()
    paced.coded(PACKETS, 0.92, intra=False)
    assert len(paced.pace(0.92, queue_delay_ms=0.0)) == 1


def handover_sequence(plan: RefreshPlanner, technology: str) -> tuple[list, list]:
    """Paced, as on the commute: reports sent every 100 ms arrive 350 ms later, the last
    before the gap sent at 80.0 s and arriving at 80.35 s; a refresh coded at 79.92 s leaves a
    packet at 79.92, 80.12 and 80.32 s (its credit at 23.2 kbit/s); held from 80.45 s; the
    next report, sent at 80.6 s, arrives at 80.85 s naming `technology`."""
    out = []
    for tick in range(1, 10):
        plan.on_report(report(79.25 + tick / 10), 79.6 + tick / 10, 30.0, False)
    plan.coded(PACKETS, 79.92, intra=False)
    arrivals = [80.05, 80.15, 80.25, 80.35]
    for frame in range(14):  # frames every 40 ms, 79.92 ... 80.44 s
        now_s = 79.92 + frame / FPS
        while arrivals and arrivals[0] <= now_s:
            arrived_s = arrivals.pop(0)
            plan.on_report(report(arrived_s - 0.35), arrived_s, 30.0, False)
        out += plan.pace(now_s, queue_delay_ms=0.0)
    for now_s in (80.5, 80.7):
        out += plan.pace(now_s, queue_delay_ms=0.0, held=True)
    handover = technology not in ("", "GPRS")
    return out, plan.on_report(report(80.6, technology), 80.85, 5.0, handover)


def test_a_handover_that_finds_part_of_a_refresh_gone_quiets_the_refresh():
    """Three packets left (79.92, 80.12 and 80.32 s), two after the receiver sent its report
    of 80.0 s (the last before the GSM one): the rest (4,320 bits, 864 ms at 5 kbit/s) is
    dropped, and with `handover_quiet` nothing is ordered or leaves until a report's queueing
    delay reads 20 ms or less."""
    plan = sending(handover_quiet=True)
    out, actions = handover_sequence(plan, "GSM")
    assert [name for name, _ in out] == ["p0", "p1", "p2"]
    assert Tally("refresh_dropped") in actions and not plan.queue
    quiet = [a for a in actions if isinstance(a, EngineEvent) and a.kind == "refresh_quiet"]
    assert len(quiet) == 1 and quiet[0].detail.startswith("8640 bits left since 80.000")
    assert plan.quiet
    assert plan.on_frame(2200, 88.0, on_model=True, budget_kbps=40.0, model_kbps=4.8)[0] is None
    plan.pace(88.04, queue_delay_ms=400.0)
    assert plan.quiet
    plan.pace(88.08, queue_delay_ms=20.0)
    assert not plan.quiet
    order, _ = plan.on_frame(2203, 88.12, on_model=True, budget_kbps=40.0, model_kbps=4.8)
    assert order is not None and order.intra


@pytest.mark.parametrize("technology", ["", "GPRS"])
def test_without_a_new_technology_the_quiet_rule_changes_nothing(technology):
    """The same sequence on a trace without labels ("") or with no handover: the same
    packets leave (the fourth at 80.9 s, on 200 ms of credit), nothing is dropped, and the
    refresh is never quiet."""
    results = []
    for quiet in (False, True):
        plan = sending(handover_quiet=quiet)
        out, actions = handover_sequence(plan, technology)
        out += plan.pace(80.9, queue_delay_ms=0.0) + plan.pace(81.3, queue_delay_ms=0.0)
        assert not plan.quiet and actions == []
        results.append(out)
    assert results[0] == results[1] and [name for name, _ in results[0]] == ["p0", "p1", "p2", "p3"]


def test_a_handover_after_a_refresh_arrived_whole_does_not_quiet_it():
    """The last packet left before the receiver sent its previous report: nothing of the
    refresh can be in the gap, so the refresh goes on."""
    plan = sending(handover_quiet=True)
    plan.coded(PACKETS[:1], 79.0, intra=False)
    assert len(plan.pace(79.0, queue_delay_ms=0.0)) == 1
    plan.on_report(report(80.0), 80.35, 30.0, False)
    assert plan.on_report(report(80.6, "GSM"), 80.85, 5.0, True) == []
    assert not plan.quiet


def test_reported_paces_but_a_packet_leaves_only_after_a_report():
    """`reported`: the credit accrues at the spare rate as `paced` (23.2 kbit/s: a 4,320-bit
    packet's worth in 186 ms), but a packet leaves only at the first frame after a report:
    p0 waits for the 0.95-s report; the credit is back above zero at 1.106 s, so p1 waits for
    the 1.15-s report (frame 1.16); then nothing until a report arrives again."""
    plan = sending(release="reported")
    plan.coded(PACKETS, 0.92, intra=False)
    left = {}
    for frame in range(23, 40):  # frames every 40 ms, 0.92 ... 1.56 s
        now_s = frame / FPS
        if frame in (24, 29):  # reports arriving at 0.95 and 1.15 s
            plan.on_report(report(now_s - 0.35), now_s - 0.01, 30.0, False)
        left[round(now_s, 2)] = [name for name, _ in plan.pace(now_s, queue_delay_ms=0.0)]
    assert {t: names for t, names in left.items() if names} == {0.96: ["p0"], 1.16: ["p1"]}
    assert len(plan.queue) == 2
