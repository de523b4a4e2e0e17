"""Issue 11's rate and quality targets on the README's data (slow: the whole bench, 150 frames a
clip). Speed targets are the benchmark's to show, not a test's. Foreman (48 raw QCIF frames,
added to the bench later) is not one of issue 11's clips: its first frames barely move, so the
frozen display and the unquantised rendering score near-identical pictures at 50-90 dB and a
mean of decibels says little; its figures are in docs/mbc.md."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def result():
    from uma.bench.mbc import default_clips, run_model_bench

    return run_model_bench(default_clips(150, seed=0), seed=0)


ISSUE_11_CLIPS = ("talking-head", "akiyo", "carphone")


def test_rates_and_quantisation_loss(result) -> None:
    for name, clip in result["clips"].items():
        assert clip["rate_kbps"] <= 2.5, name  # light and body motion included
        if name not in ISSUE_11_CLIPS:
            continue
        assert clip["wire_kbps"] <= 4.8, name
        assert clip["psnr_loss_db"] < 0.5, name


def test_talking_head_is_tracked_to_half_a_pixel_without_losing_it(result) -> None:
    head = result["clips"]["talking-head"]
    assert head["mde_median_px"] <= 0.5
    assert head["lost_tracks"] == 0 and head["failures"] == 0


def test_real_clips_beat_the_frozen_display_in_the_face(result) -> None:
    from uma.video import load_ladder

    fifth_kbps = load_ladder().rungs[0].rate_kbps / 5
    real = [n for n in result["clips"] if n != "talking-head" and n in ISSUE_11_CLIPS]
    if not real:
        pytest.skip("../shared/data absent")
    for name in real:
        face = result["clips"][name]["face"]
        assert face["quantised"]["psnr_db"] > face["frozen"]["psnr_db"], name
        assert face["quantised"]["ssim"] > face["frozen"]["ssim"], name
        assert result["clips"][name]["rate_kbps"] < fifth_kbps, name
