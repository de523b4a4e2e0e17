"""`scripts/mbc_transformed.py`: akiyo's clicked points moved with each transformed clip."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import mbc_transformed as mt  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def points() -> dict:
    return yaml.safe_load((ROOT / mt.POINTS).read_text())["points"]


def test_every_pair_names_points_of_akiyo_s_file(points):
    assert all(a in points and b in points for a, b in mt.PAIRS)


def test_mirroring_swaps_the_subject_s_sides_and_twice_is_the_original(points):
    once = mt.moved_points("mirrored", points)
    assert once["3.5"] == [mt.WIDTH - 1 - points["3.6"][0], points["3.6"][1]]  # left pupil
    assert once["9.3"] == [mt.WIDTH - 1 - points["9.3"][0], points["9.3"][1]]  # nose tip
    # the subject's left pupil stays on the viewer's right of the right pupil
    assert once["3.5"][0] > once["3.6"][0]
    assert mt.moved_points("mirrored", once) == points


def test_qcif_halves_pixel_centres(points):
    half = mt.moved_points("qcif", points)
    assert half["9.3"] == [(points["9.3"][0] + 0.5) / 2 - 0.5, (points["9.3"][1] + 0.5) / 2 - 0.5]
    assert mt.moved_points("dim", points) == points


def test_the_clips_pictures():
    picture = np.arange(2 * 4 * 3, dtype=np.uint8).reshape(2, 4, 3)
    assert np.array_equal(mt.mirrored(picture, 0), picture[:, ::-1])
    bright = np.full((2, 2, 3), 100, np.uint8)
    assert mt.dim(bright, 0)[0, 0, 0] == 97  # 100 x 0.85 + 12
    assert mt.dim(bright, 45)[0, 0, 0] == 107  # 100 x 0.95 + 12, a quarter period on


def test_rolling_leaves_frame_0_and_turns_about_the_face_to_its_peak():
    picture = np.zeros((mt.HEIGHT, mt.WIDTH, 3), np.uint8)
    x, y = (round(v) for v in mt._face_centre())
    picture[y, x + 40] = 255  # a dot 40 px right of the face's centre
    assert np.array_equal(mt.rolled(picture, 0), picture)
    peak = mt.rolled(picture, 75)  # sin^2 = 1: turned by ROLL_PEAK_RAD
    ys, xs = np.nonzero(peak[..., 0] > 60)
    # OpenCV's positive angle turns counter-clockwise on screen (y down): the dot goes up
    angle = np.arctan2(y - ys.mean(), xs.mean() - x)
    assert abs(angle - mt.ROLL_PEAK_RAD) < 0.05, angle


@pytest.mark.parametrize("name", ["wide", "wide169", "portrait", "closeup"])
def test_a_point_moves_with_the_picture(points, name):
    """A bright spot under the nose tip lands where the moved point says, within a pixel."""
    change, size, every = mt.CLIPS[name]
    x, y = (int(round(v)) for v in points["9.3"])
    picture = np.zeros((mt.HEIGHT, mt.WIDTH, 3), np.uint8)
    picture[y - 2 : y + 3, x - 2 : x + 3] = 255
    moved = change(picture, 0)
    assert moved.shape[1::-1] == size and every == 1
    weights = np.clip(moved[..., 0].astype(float) - 128.0, 0.0, None)  # the spot, not the border
    rows, cols = np.indices(weights.shape)
    centre = np.array([(cols * weights).sum(), (rows * weights).sum()]) / weights.sum()
    assert np.hypot(*(centre - mt.moved_points(name, {"9.3": [x, y]})["9.3"])) < 1.0
