import dataclasses
import json

import cv2
import numpy as np
import pytest

from uma.cli import main
from uma.face import (
    Motion,
    TalkingHeadSource,
    rasterize,
    sample_bilinear,
    visible_triangles,
    warp_points,
)
from uma.metrics.quality import psnr_db

STILL_LIGHT = Motion(light_gain=0.0, light_angle_rad=0.0, noise_std=0.0)


@pytest.fixture(scope="module")
def clean_source():
    return TalkingHeadSource(176, 144, seed=3, motion=STILL_LIGHT)


def _code(labels: np.ndarray) -> np.ndarray:
    """Triangle numbers as three-channel colours no bilinear blend of two labels reproduces."""
    return np.dstack([labels, 255 - labels, (labels * 37) % 256]).astype(np.uint8)


def test_ground_truth_is_where_each_triangle_is_drawn(clean_source):
    # Texture the face with its own triangle numbers, render, and find each triangle's pixels:
    # their centre must be where the ground-truth points put that triangle's texture.
    source = clean_source
    triangles = source.model.triangles
    raster = rasterize(source.template_points, triangles, (144, 176))
    labels = np.zeros((144, 176), np.int32)
    labels[raster.ys, raster.xs] = raster.tri + 1
    labelled = dataclasses.replace(source.description, texture=_code(labels))
    painted = TalkingHeadSource(176, 144, seed=3, motion=STILL_LIGHT, description=labelled)
    for index in (11, 60, 140):
        frame = painted.render_bgr(index).astype(np.int32)
        truth = painted.ground_truth(index)
        visible = visible_triangles(painted.model, truth["params"])
        errors = []
        for t in np.flatnonzero(visible):
            source_px = np.column_stack([raster.xs, raster.ys])[raster.tri == t]
            if len(source_px) < 25:
                continue
            code = _code(np.array([t + 1]))[0].astype(np.int32)
            ys, xs = np.nonzero(np.all(frame == code, axis=2))
            # A rare blend of two other labels can mimic the code far away: look near the truth.
            corners = truth["points"][triangles[t]]
            low, high = corners.min(axis=0) - 3, corners.max(axis=0) + 3
            near = (xs >= low[0]) & (xs <= high[0]) & (ys >= low[1]) & (ys <= high[1])
            if near.sum() < 0.5 * len(source_px):
                continue  # mostly hidden behind a nearer triangle
            # The labelled pixels' centre, carried by triangle t's own affine map.
            a, b, c = source.template_points[triangles[t]]
            weights = np.linalg.solve(np.column_stack([b - a, c - a]), source_px.mean(axis=0) - a)
            ta, tb, tc = corners
            expected = ta + weights[0] * (tb - ta) + weights[1] * (tc - ta)
            errors.append([xs[near].mean(), ys[near].mean()] - expected)
        errors = np.array(errors)
        assert len(errors) > 50
        # No systematic offset; a small or partly hidden triangle is off by a pixel at most.
        assert np.linalg.norm(errors.mean(axis=0)) < 0.15
        assert np.median(np.linalg.norm(errors, axis=1)) < 0.4
        assert np.linalg.norm(errors, axis=1).max() < 2.0


def test_ground_truth_warps_frames_back_onto_the_template(clean_source):
    source = clean_source
    template = cv2.cvtColor(source.description.texture, cv2.COLOR_BGR2GRAY)
    raster = rasterize(source.template_points, source.model.triangles, template.shape)
    interior = raster.bary.min(axis=1) > 0.05
    original = template[raster.ys, raster.xs].astype(np.float32)[interior]
    for index in (7, 40, 90):
        frame = cv2.cvtColor(source.render_bgr(index), cv2.COLOR_BGR2GRAY)
        truth = source.ground_truth(index)
        samples = sample_bilinear(frame, warp_points(raster, truth["points"]))[interior]
        # Two bilinear resamplings of a small face, and texture the mouth opening stretches.
        assert psnr_db(original, samples) > 32
        wrong = sample_bilinear(frame, warp_points(raster, source.template_points))[interior]
        assert psnr_db(original, wrong) < psnr_db(original, samples) - 10


def test_whole_frame_moves_without_seams(clean_source):
    # Every pixel comes from the one continuous mesh: the head ring carries hair and neck.
    source = clean_source
    for index in (25, 75, 150):
        params = source.params_at(index)
        points = source.scene.points(params)
        raster = rasterize(points, source.scene.triangles, (144, 176))
        assert raster.size == 144 * 176
    # Far from the face the picture hardly moves; next to it, it moves with the head.
    first, later = source.render_bgr(0).astype(int), source.render_bgr(60).astype(int)
    corner = np.abs(first[:12, :12] - later[:12, :12]).mean()
    assert corner < 4 < np.abs(first - later).mean() * 3


def test_light_changes_gain_and_direction():
    motion = Motion(yaw_rad=0, pitch_rad=0, roll_rad=0, shift_frac=0, scale_frac=0, speech=0)
    motion = dataclasses.replace(motion, blinks=False, noise_std=0.0)
    source = TalkingHeadSource(176, 144, seed=0, motion=motion)
    base = source.render_bgr(0).astype(np.float32) + 1
    gains, sides = [], []
    face = source.template_points
    left = int(face[:, 0].min() + 0.2 * np.ptp(face[:, 0]))
    right = int(face[:, 0].max() - 0.2 * np.ptp(face[:, 0]))
    rows = slice(int(face[:, 1].mean()) - 8, int(face[:, 1].mean()) + 8)
    for index in range(0, 750, 50):
        ratio = (source.render_bgr(index).astype(np.float32) + 1) / base
        gains.append(source.ground_truth(index)["light_gain"])
        sides.append(ratio[rows, right - 4 : right].mean() - ratio[rows, left : left + 4].mean())
        direction = source.ground_truth(index)["light_direction"]
        assert np.isclose(np.linalg.norm(direction), 1.0)
    assert np.ptp(gains) > 0.2
    # A light from the side brightens one cheek relative to the other, and swings over.
    assert max(sides) > 0.05 and min(sides) < -0.05


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
    blinks = [a.params_at(i)[6 + a.model.action_unit_names.index("eye_close")] for i in range(250)]
    assert max(blinks) > 0.9


def test_bad_source_settings():
    with pytest.raises(ValueError, match="light_gain"):
        Motion(light_gain=-0.1)
    source = TalkingHeadSource(176, 144, motion=STILL_LIGHT)
    with pytest.raises(ValueError, match="176x144"):
        TalkingHeadSource(352, 288, description=source.description)


def test_source_synth_cli_writes_clip_and_truth(tmp_path):
    out = tmp_path / "clip.mp4"
    assert main(["source", "synth", "--out", str(out), "--frames", "12", "--size", "176x144"]) == 0
    truth = json.loads(out.with_suffix(".truth.json").read_text())
    assert len(truth["frames"]) == 12
    assert len(truth["frames"][0]["params"]) == len(truth["param_names"])
    source = TalkingHeadSource(176, 144, seed=0)
    assert np.allclose(truth["frames"][5]["params"], source.params_at(5), atol=1e-5)
    assert np.allclose(truth["frames"][5]["points_px"], source.ground_truth(5)["points"], atol=1e-3)
    from uma.video import VideoFileSource

    decoded = list(VideoFileSource(out).frames())
    assert len(decoded) == 12
    # High quality: the clip is the source's frames up to coding noise.
    frames = list(TalkingHeadSource(176, 144, seed=0, frame_count=12).frames())
    assert psnr_db(frames[5][:144].astype(np.float32), decoded[5][:144].astype(np.float32)) > 38


def test_source_synth_cli_bad_output(tmp_path, capsys):
    blocked = tmp_path / "file"
    blocked.write_text("")
    assert main(["source", "synth", "--out", str(blocked / "c.mp4"), "--frames", "2"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("uma: error:") and err.count("\n") == 1
    assert "existing file" in err and str(blocked) in err


def test_the_compiled_maps_and_light_are_the_numpy_forms_to_the_bit():
    from uma.face.talking_head_kernels import light_and_noise, pixel_maps

    rng = np.random.default_rng(5)
    height, width, triangles = 23, 31, 7
    table = rng.normal(0, 3, (triangles + 1, 3, 3)).astype(np.float32)
    labels = rng.integers(-1, triangles, (height, width)).astype(np.int32)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    per_pixel = table[labels]
    maps = per_pixel[..., 0] * xs[..., None] + per_pixel[..., 1] * ys[..., None] + per_pixel[..., 2]
    map_x, map_y, light = pixel_maps(table, labels)
    assert np.array_equal(map_x, maps[..., 0]) and np.array_equal(map_y, maps[..., 1])
    assert np.array_equal(light, maps[..., 2])

    sampled = rng.integers(0, 256, (height, width, 3)).astype(np.uint8)
    noise = rng.standard_normal(sampled.shape, dtype=np.float32)
    gain = 1.0123456789
    frame = sampled.astype(np.float32)
    frame *= (gain * light)[..., None]
    frame += 2.0 * noise
    expected = np.clip(np.rint(frame), 0, 255).astype(np.uint8)
    got = light_and_noise(sampled, light, np.float32(gain), noise, np.float32(2.0))
    assert np.array_equal(got, expected)
