"""The rate policy's climb after its hold (`PolicyView.climb`), on hand-worked views of the
H.264 ladder's shape: same-size rungs retarget the encoder, a new size costs a keyframe."""

import pytest

from uma.engine.points import OperatingPoint
from uma.engine.policy import UPSIZE_MARGIN, PolicyView, oracle_policy, throughput_policy

# (rate kbit/s, width, height, frames/s): codecs/h264.yaml's rungs.
RUNGS = (
    (16, 128, 96, 5.0),
    (24, 176, 144, 5.0),
    (40, 176, 144, 8.333333),
    (64, 256, 208, 12.5),
    (128, 256, 208, 12.5),
    (256, 352, 288, 12.5),
    (384, 352, 288, 25.0),
    (768, 352, 288, 25.0),
    (1200, 352, 288, 25.0),
)
POINTS = tuple(OperatingPoint("h264", rate, fps, w, h) for rate, w, h, fps in RUNGS)


def view(**kw):
    base = dict(
        now_s=10.0, points=POINTS, current=5, last_switch_s=8.0, estimate_kbps=1000.0,
        safety=0.85, up_hold_s=1.0, climb="stream",
    )  # fmt: skip
    base.update(kw)
    return PolicyView(**base)


def test_a_same_size_climb_goes_to_the_highest_rung_the_budget_carries_at_once():
    # budget 0.85 x 1000 = 850: 768 fits, 1200 does not; from 256 (CIF) to 768 (CIF) at once
    assert throughput_policy(view()) == 7
    # the default climb: one rung
    assert throughput_policy(view(climb="step")) == 6
    # within the hold: no climb either way
    assert throughput_policy(view(last_switch_s=9.5)) == 5
    assert throughput_policy(view(last_switch_s=9.5, climb="step")) == 5


def test_a_same_size_climb_stops_at_a_new_size():
    # from 64 (256x208): 128 is the same size, 256 (CIF) is not: stop at 128 though 768 fits
    assert throughput_policy(view(current=3)) == 4
    # from 24 (QCIF) with budget 850: 40 is the last QCIF rung
    assert throughput_policy(view(current=1)) == 2


def test_a_new_size_is_still_one_step_and_only_with_the_margin():
    # from 128 (256x208) with budget 850: up one rung to 256 (CIF), not to 768
    assert throughput_policy(view(current=4)) == 5
    # budget 300 carries 256 but not 1.25 x 256 = 320: stay
    assert UPSIZE_MARGIN * 256 > 0.85 * (300 / 0.85)
    assert throughput_policy(view(current=4, estimate_kbps=300 / 0.85)) == 4
    # budget 330 >= 320: up one
    assert throughput_policy(view(current=4, estimate_kbps=330 / 0.85)) == 5


def test_down_is_still_at_once():
    # from 1200 with budget 0.85 x 100 = 85: to 64 at once, within the hold
    assert throughput_policy(view(current=8, estimate_kbps=100.0, last_switch_s=9.99)) == 3


def test_fit_climbs_across_sizes_at_once_with_the_margin_on_the_new_size():
    # from 16 (SQCIF), budget 850: 768 (CIF) fits but 1.25 x 768 = 960 > 850; 384 (CIF) has it
    assert throughput_policy(view(current=0, climb="fit")) == 6
    # from 384 (CIF): 768 is the same stream, no margin needed
    assert throughput_policy(view(current=6, climb="fit")) == 7
    # budget 20 x 0.85 = 17 from 16: 24 (QCIF) fits but not with the margin: stay
    assert throughput_policy(view(current=0, climb="fit", estimate_kbps=20.0 / 0.85)) == 0


def test_the_oracle_climbs_as_the_view_says():
    assert oracle_policy(view(capacity_kbps=1000.0, estimate_kbps=1.0)) == 7
    assert oracle_policy(view(capacity_kbps=1000.0, estimate_kbps=1.0, climb="step")) == 6


def test_an_unknown_climb_is_refused_by_name():
    with pytest.raises(ValueError, match="'leap'"):
        view(climb="leap")
