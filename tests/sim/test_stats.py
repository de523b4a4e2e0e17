"""Each part's tally: bits offered by kind, frozen into the result."""

import dataclasses

import pytest

from uma.sim.stats import DescriptionStats, ModelStats, RefreshStats, SentBits


def test_sent_bits_count_their_own_kinds_only():
    sent = SentBits()
    sent.add("refresh", 1200)
    sent.add("refresh", 800)
    sent.add("padding", 40)
    sent.add("video", 9600)  # the codecs' own bits are in the frame log, not here
    assert (sent.description, sent.refresh, sent.padding) == (0, 2000, 40)


@pytest.mark.parametrize("stats", [ModelStats(), DescriptionStats(), RefreshStats()])
def test_a_finished_runs_stats_are_frozen(stats):
    name = dataclasses.fields(stats)[0].name
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(stats, name, 1)
