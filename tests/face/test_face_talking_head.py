import json

import cv2
import numpy as np
import pytest

from uma.cli import main
from uma.face import Motion, TalkingHeadSource, rasterize, sample_bilinear, warp_points
from uma.metrics.quality import psnr_db


@pytest.fixture(scope="module")
def clean_source():
    motion = Motion(light_gain=0.0, light_gradient=0.0, noise_std=0.0)
    return TalkingHeadSource(176, 144, seed=3, motion=motion)


def test_ground_truth_matches_what_is_rendered(clean_source):
    source = clean_source
    template = cv2.cvtColor(source.description.texture, cv2.COLOR_BGR2GRAY)
    raster = rasterize(source.template_points, source.model.triangles, template.shape)
    interior = raster.bary.min(axis=1) > 0.05
    original = template[raster.ys, raster.xs].astype(np.float32)[interior]
    for index in (7, 40, 90):
        frame = cv2.cvtColor(source.render_bgr(index), cv2.COLOR_BGR2GRAY)
        truth = source.ground_truth(index)
        samples = sample_bilinear(frame, warp_points(raster, truth["points"]))[interior]
        # Occluded triangles (head turned) and the mouth opening move texture; most pixels agree.
        assert psnr_db(original, samples) > 24
        # And the truth is not trivially the template pose.
        wrong = sample_bilinear(frame, warp_points(raster, source.template_points))[interior]
        assert psnr_db(original, samples) > psnr_db(original, wrong) + 3 or index == 0


def test_source_is_deterministic_and_moves():
    a = TalkingHeadSource(176, 144, seed=1, frame_count=30)
    b = TalkingHeadSource(176, 144, seed=1, frame_count=30)
    fa, fb = list(a.frames()), list(b.frames())
    assert len(fa) == 30 and fa[0].shape == (216, 176)
    assert all(np.array_equal(x, y) for x, y in zip(fa, fb, strict=True))
    assert np.abs(fa[0].astype(int) - fa[29].astype(int)).mean() > 1
    motion = np.array([a.params_at(i) for i in range(0, 250, 5)])
    assert np.ptp(motion[:, 4]) > 0.1  # head turns
    assert np.ptp(motion[:, 6]) > 0.2  # the jaw moves


def test_source_synth_cli_writes_clip_and_truth(tmp_path):
    out = tmp_path / "clip.mp4"
    assert main(["source", "synth", "--out", str(out), "--frames", "12", "--size", "176x144"]) == 0
    truth = json.loads(out.with_suffix(".truth.json").read_text())
    assert len(truth["frames"]) == 12
    assert len(truth["frames"][0]["params"]) == len(truth["param_names"])
    from uma.video import VideoFileSource

    assert len(list(VideoFileSource(out).frames())) == 12
