from itertools import islice

import numpy as np
import pytest

import uma.sim.kept_source as kept_source
from uma.config.scenario import SourceConfig
from uma.sim.sources import _open, open_source

HEAD = SourceConfig(kind="talking-head", width=176, height=144, fps=25)


@pytest.fixture(autouse=True)
def _nothing_kept(monkeypatch):
    monkeypatch.setattr(kept_source, "_KEPT", {})


def first(source, count):
    return list(islice(source.frames(), count))


def same(frames, reference):
    return len(frames) == len(reference) and all(map(np.array_equal, frames, reference))


def test_a_second_run_replays_the_first_runs_frames_and_renders_on(monkeypatch):
    reference = first(_open(HEAD, seed=3), 12)
    assert same(first(open_source(HEAD, seed=3), 8), reference[:8])
    renders = []
    monkeypatch.setattr(kept_source, "_Kept", _counting(kept_source._Kept, renders))
    second = first(open_source(HEAD, seed=3), 12)  # 8 replayed, 4 rendered on
    assert same(second, reference) and renders == []
    second[0][:] = 0  # a run writing into its frame changes no later run's
    assert same(first(open_source(HEAD, seed=3), 12), reference)


def test_other_settings_or_seed_are_rendered_afresh():
    three = first(open_source(HEAD, seed=3), 5)
    four = first(open_source(HEAD, seed=4), 5)
    assert same(four, first(_open(HEAD, seed=4), 5)) and not same(four, three)
    pattern = SourceConfig(kind="pattern", width=64, height=48, fps=25)
    assert same(first(open_source(pattern, seed=4), 5), first(_open(pattern, seed=4), 5))


def test_past_the_bound_a_run_that_falls_behind_renders_from_its_own_source(monkeypatch):
    reference = first(_open(HEAD, seed=3), 14)
    monkeypatch.setattr(kept_source, "KEEP_BYTES", reference[0].nbytes * 4)
    front = open_source(HEAD, seed=3).frames()
    ahead = [next(front) for _ in range(8)]  # 4 kept; the shared renderer is 8 in
    behind = first(open_source(HEAD, seed=3), 14)  # 4 replayed, then a source of its own
    ahead += [next(front) for _ in range(6)]
    assert same(ahead, reference) and same(behind, reference)


def test_a_kept_source_is_the_source_but_for_its_frames():
    source = open_source(HEAD, seed=3)
    assert (source.width, source.height, source.fps, source.name) == (
        176,
        144,
        25.0,
        "talking-head",
    )
    assert source.ground_truth(2)["frame"] == 2


def _counting(cls, made):
    def make(source):
        made.append(source)
        return cls(source)

    return make
