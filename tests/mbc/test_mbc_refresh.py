"""The model-aided refresh's schedule (`uma.mbc.refresh`): which picture serves which frame."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uma.mbc import RefreshUnit, SceneError, refresh_frames, schedule_refresh


def test_refresh_frames_at_a_low_rate_of_a_ntsc_clip() -> None:
    assert refresh_frames(10, 25.0, 5.0) == [0, 5]
    assert refresh_frames(150, 30000 / 1001, 1.0)[:3] == [0, 30, 60]
    frames = refresh_frames(150, 30000 / 1001, 2.5)
    assert frames[:3] == [0, 12, 24] and frames[-1] < 150 and len(frames) == len(set(frames))
    assert refresh_frames(4, 25.0, 25.0) == [0, 1, 2, 3]


@pytest.mark.parametrize(
    "args", [(0, 25.0, 5.0), (10, 25.0, 0.0), (10, 25.0, 30.0), (10, math.nan, 5.0)]
)
def test_refresh_frames_refuses_bad_rates(args) -> None:
    with pytest.raises(SceneError, match="refresh"):
        refresh_frames(*args)


def test_an_instant_channel_serves_each_picture_on_its_own_frame() -> None:
    units = [RefreshUnit(0, 8000, keyframe=True), RefreshUnit(5, 2000)]
    schedule = schedule_refresh(units, 10, 25.0, math.inf)
    assert schedule.serving.tolist() == [0] * 5 + [1] * 5
    assert schedule.delay_frames().tolist() == [0, 0]


def test_a_unit_serves_after_its_transmission_time_and_queues_behind_the_one_before() -> None:
    # 10 kbit/s: the 8 kbit keyframe takes 0.8 s (20 frames at 25/s), the 1 kbit unit of frame
    # 5 waits for it and then takes 0.1 s more: it arrives at 0.9 s, frame 22.5 -> 23.
    units = [RefreshUnit(0, 8000, keyframe=True), RefreshUnit(5, 1000), RefreshUnit(40, 1000)]
    schedule = schedule_refresh(units, 50, 25.0, 10.0)
    assert schedule.serves_from.tolist() == [20, 23, 43]
    assert np.allclose(schedule.arrival_s, [0.8, 0.9, 1.7])
    expected = [-1] * 20 + [0] * 3 + [1] * 20 + [2] * 7
    assert schedule.serving.tolist() == expected
    assert schedule.delay_frames().tolist() == [20, 18, 3]
    later = schedule_refresh(units, 50, 25.0, 10.0, latency_s=0.2)
    assert later.serves_from.tolist() == [25, 28, 48]


def test_a_lost_unit_leaves_the_last_good_reference_until_the_next_keyframe() -> None:
    units = [
        RefreshUnit(0, 100, keyframe=True),
        RefreshUnit(5, 100, lost=True),
        RefreshUnit(10, 100),  # predicts from the lost one: undecodable
        RefreshUnit(15, 100, keyframe=True),
    ]
    schedule = schedule_refresh(units, 20, 25.0, math.inf)
    assert schedule.serving.tolist() == [0] * 15 + [3] * 5
    assert schedule.serves_from.tolist() == [0, -1, -1, 15]
    assert np.isnan(schedule.arrival_s[1:3]).all()


def test_a_unit_arriving_after_the_clip_never_serves() -> None:
    schedule = schedule_refresh([RefreshUnit(8, 4000, keyframe=True)], 10, 25.0, 10.0)
    assert schedule.serving.tolist() == [-1] * 10 and schedule.serves_from.tolist() == [-1]


@pytest.mark.parametrize(
    "units, match",
    [
        ([RefreshUnit(3, 10), RefreshUnit(3, 10)], "refresh unit 1"),
        ([RefreshUnit(12, 10)], "refresh unit 0"),
        ([RefreshUnit(0, -1)], "size_bits"),
    ],
)
def test_bad_units_are_named(units, match) -> None:
    with pytest.raises(SceneError, match=match):
        schedule_refresh(units, 10, 25.0, 10.0)


def test_bad_rate_or_latency_is_refused() -> None:
    with pytest.raises(SceneError, match="rate_kbps"):
        schedule_refresh([], 10, 25.0, 0.0)
    with pytest.raises(SceneError, match="latency_s"):
        schedule_refresh([], 10, 25.0, 10.0, latency_s=-1.0)
