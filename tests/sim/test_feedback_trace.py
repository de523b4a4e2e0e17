"""`feedback.trace`: reports ride the uplink's measured capacity, in order, instead of being
lost whenever the downlink's capacity is zero (hand-worked), and the key's bad values."""

import re

import numpy as np
import pytest
import simpy

from uma.config import load_scenario
from uma.errors import ConfigError
from uma.sim.capacity import CapacitySchedule
from uma.sim.links import LinkProps
from uma.sim.state import FEEDBACK_BYTES, World

DELAY_S = 0.02


def _world(env, feedback_capacity):
    """A world with only what `send_feedback` reads: the downlink silent for its first second."""
    fields = dict.fromkeys(
        ("scenario", "frames", "fps", "source_iter", "ladder", "engine", "uplink", "downlink",
         "receiver", "log", "codec", "quality"),
    )  # fmt: skip
    return World(
        env=env, capacity=CapacitySchedule([0.0, 1.0], [0.0, 1e6]),
        link_props=lambda technology: LinkProps(delay_s=DELAY_S, loss_rate=0.0),
        feedback_rng=np.random.default_rng(0), feedback_capacity=feedback_capacity, **fields,
    )  # fmt: skip


def _arrivals(feedback_capacity):
    """Reports sent at 0.2 s and 0.3 s (and 1.2 s): when each arrived, and how many were lost."""
    env = simpy.Environment()
    world, arrived = _world(env, feedback_capacity), []

    def send(at_s, name):
        yield env.timeout(at_s)
        world.send_feedback(name, lambda item, now_s: arrived.append((item, round(now_s, 9))))

    for at_s, name in ((0.2, "a"), (0.3, "b"), (1.2, "c")):
        env.process(send(at_s, name))
    env.run()
    return arrived, world.feedback_lost


def test_without_a_measured_uplink_a_silent_downlink_loses_the_reports():
    assert _arrivals(None) == ([("c", 1.2 + DELAY_S)], 2)


def test_reports_wait_for_the_uplinks_capacity_in_order():
    # Silent until 0.5 s, then one report a tenth of a second: a waits until 0.5 s and is sent
    # by 0.6 s; b, sent at 0.3 s, waits behind it until 0.7 s; c meets a free uplink at 1.2 s.
    rate_bps = 8 * FEEDBACK_BYTES / 0.1
    uplink = CapacitySchedule([0.0, 0.5], [0.0, rate_bps])
    arrived, lost = _arrivals(uplink)
    assert lost == 0
    assert arrived == [("a", 0.6 + DELAY_S), ("b", 0.7 + DELAY_S), ("c", 1.3 + DELAY_S)]


def test_an_uplink_that_never_comes_back_loses_the_report():
    arrived, lost = _arrivals(CapacitySchedule([0.0], [0.0]))
    assert arrived == [] and lost == 3


def _refused(tmp_path, text, pattern):
    path = tmp_path / "s.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError) as caught:
        load_scenario(path)
    message = str(caught.value)
    assert "\n" not in message and re.search(pattern, message), message


def test_the_key_needs_one_trace_segment_and_an_existing_file(tmp_path):
    (tmp_path / "down.csv").write_text("time_s,rate_kbps\n0,100\n10,100\n")
    (tmp_path / "up.csv").write_text("time_s,rate_kbps\n0,50\n10,50\n")
    generated = "name: x\nroute:\n  - {technology: 3G, duration_s: 5}\n"
    traced = "name: x\nroute:\n  - {technology: 3G, duration_s: 5, trace: down.csv}\n"
    _refused(tmp_path, generated + "feedback: {trace: up.csv}\n",
             r"s\.yaml:4 \(feedback\.trace\): expected a route of one trace segment")  # fmt: skip
    _refused(tmp_path, traced + "feedback: {trace: nowhere.up}\n",
             r"\(feedback\.trace\): expected an existing file")  # fmt: skip
    (tmp_path / "s.yaml").write_text(traced + "feedback: {trace: up.csv}\n")
    assert load_scenario(tmp_path / "s.yaml").feedback.trace == str(tmp_path / "up.csv")


def test_the_uplink_is_read_from_the_segments_offset(tmp_path):
    from uma.sim.world import feedback_capacity

    (tmp_path / "down.csv").write_text("time_s,rate_kbps\n0,100\n10,100\n")
    (tmp_path / "up.csv").write_text("time_s,rate_kbps\n0,50\n2,80\n3,0\n10,0\n")
    route = "  - {technology: 3G, duration_s: 5, offset_s: 2, trace: down.csv}\n"
    (tmp_path / "s.yaml").write_text(f"name: x\nroute:\n{route}feedback: {{trace: up.csv}}\n")
    uplink = feedback_capacity(load_scenario(tmp_path / "s.yaml"))
    assert uplink.rate_kbps_at(0.5) == 80.0 and uplink.rate_kbps_at(1.5) == 0.0
    (tmp_path / "s.yaml").write_text(f"name: x\nroute:\n{route}")
    assert feedback_capacity(load_scenario(tmp_path / "s.yaml")) is None


def test_an_outage_fault_silences_the_uplink_too(tmp_path):
    from uma.sim.world import feedback_capacity

    (tmp_path / "down.csv").write_text("time_s,rate_kbps\n0,100\n10,100\n")
    (tmp_path / "up.csv").write_text("time_s,rate_kbps\n0,50\n10,50\n")
    (tmp_path / "s.yaml").write_text(
        "name: x\nroute:\n  - {technology: 3G, duration_s: 5, trace: down.csv}\n"
        "feedback: {trace: up.csv}\nfaults: {outages: [{start_s: 1, duration_s: 2}]}\n"
    )
    uplink = feedback_capacity(load_scenario(tmp_path / "s.yaml"))
    assert [uplink.rate_kbps_at(t) for t in (0.5, 1.5, 2.9, 3.5)] == [50.0, 0.0, 0.0, 50.0]


def test_a_bad_uplink_file_is_named_by_its_key(tmp_path):
    from uma.errors import TraceError
    from uma.sim.world import feedback_capacity

    (tmp_path / "down.csv").write_text("time_s,rate_kbps\n0,100\n10,100\n")
    (tmp_path / "bad.up").write_text("abc\n")
    route = "  - {technology: 3G, duration_s: 5, trace: down.csv}\n"
    (tmp_path / "s.yaml").write_text(f"name: x\nroute:\n{route}feedback: {{trace: bad.up}}\n")
    with pytest.raises(TraceError) as caught:
        feedback_capacity(load_scenario(tmp_path / "s.yaml"))
    message = str(caught.value)
    assert message.startswith("feedback.trace (") and "line 1 of" in message
    assert "route segment" not in message and "\n" not in message
