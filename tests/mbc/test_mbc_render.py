"""The receiver's renderer: the description's texture at given parameters, over a background."""

from __future__ import annotations

import numpy as np

from uma.mbc.decoder import FaceRenderer
from uma.metrics.quality import psnr_db


def test_rendering_at_the_template_pose_gives_back_the_template(head) -> None:
    description = head.description
    renderer = FaceRenderer(description, (352, 288), background=np.zeros((288, 352), np.uint8))
    image, mask = renderer.render(description.params)
    assert image.shape == (288, 352) and image.dtype == np.uint8
    assert 0.1 < mask.mean() < 0.5
    gray = description.gray
    assert psnr_db(gray[mask], image[mask]) > 40
    assert not image[~mask].any()  # the background is left as it was


def test_rendering_follows_the_parameters(head, head_frames) -> None:
    renderer = FaceRenderer(head.description, (352, 288), background=head_frames[0])
    params = head.params_at(7)
    image, mask = renderer.render(params)
    # Against the true frame (its light and noise differ, so not exact), far better than the
    # template's own pose.
    at_template, _ = renderer.render(head.description.params)
    truth = head_frames[7]
    assert psnr_db(truth[mask], image[mask]) > psnr_db(truth[mask], at_template[mask]) + 3


def test_default_background_is_the_texture_where_it_was_cut(head) -> None:
    renderer = FaceRenderer(head.description, (352, 288))
    assert np.array_equal(renderer.background, head.description.gray)
    far = head.description.params.copy()
    far[0] = -1000.0  # the face entirely off the picture
    image, mask = renderer.render(far)
    assert not mask.any() and np.array_equal(image, renderer.background)
