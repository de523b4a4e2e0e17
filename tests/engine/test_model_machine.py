"""The model codec's sub-machine: its one transition table, and what it says while wanted."""

import pytest
from recorded import Recorded

from uma.engine.model import TRANSITIONS, ModelEvent, ModelMachine, ModelState, Want


def machine(unavailable=""):
    m = Recorded(ModelMachine("mbc", unavailable=unavailable, retry_s=2.0, ladder_label="H.264"))
    m.keep(m.part.declared())
    return m, m.events, m.counts


def test_the_table_has_one_path_to_on_and_abandon_from_everywhere():
    assert TRANSITIONS[(ModelState.OFF, ModelEvent.START)] is ModelState.INITIALISING
    assert TRANSITIONS[(ModelState.INITIALISING, ModelEvent.INIT_OK)] is ModelState.READY
    assert TRANSITIONS[(ModelState.READY, ModelEvent.USE)] is ModelState.ON
    assert all(TRANSITIONS[(s, ModelEvent.ABANDON)] is ModelState.OFF for s in ModelState)
    into_on = [key for key, state in TRANSITIONS.items() if state is ModelState.ON]
    assert into_on == [(ModelState.READY, ModelEvent.USE)]


def test_an_event_the_table_lacks_is_an_error():
    m, _, _ = machine()
    with pytest.raises(RuntimeError, match="no transition from OFF on USE"):
        m.fire(ModelEvent.USE)


def test_start_initialise_use_then_a_lost_track_blocks_for_retry():
    m, events, counts = machine()
    assert m.want(0.0, description_ready=True) is Want.START
    m.start(0.0, 12.0)
    assert m.want(0.1, description_ready=True) is Want.LADDER  # initialising
    m.init_done(True, 0.2, reason="ok", evaluations=5)
    assert m.state is ModelState.READY
    assert m.want(0.3, description_ready=True) is Want.MODEL
    assert m.state is ModelState.READY  # a query changes nothing
    m.use()
    assert m.state is ModelState.ON
    assert m.track_failed("face left", 1.0)
    assert m.want(1.5, description_ready=True) is Want.LOWEST  # blocked until 3.0
    assert m.want(3.1, description_ready=True) is Want.START
    kinds = [kind for _, kind, _ in events]
    assert kinds == ["mbc_init_start", "mbc_init_done", "mbc_track_failed"]
    assert counts["inits"] == 1 and counts["track_failures"] == 1


def test_refused_once_without_a_description_and_waits_for_delivery():
    m, events, counts = machine("no content description")
    for t in (0.0, 1.0, 2.0):
        assert m.want(t, description_ready=True) is Want.LOWEST
        m.refuse(t)
    assert [kind for _, kind, _ in events] == ["mbc_refused"]
    assert events[0][2] == "no content description; lowest H.264 rung"
    assert counts["mbc_refused"] == 1
    m2, _, _ = machine()
    assert m2.want(0.0, description_ready=False) is Want.WAIT
