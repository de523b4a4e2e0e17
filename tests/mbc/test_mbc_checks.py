"""`check_description`: a face cut by the picture's edge passes, a model off its texture fails."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from uma.errors import FaceError
from uma.face import TalkingHeadSource
from uma.mbc.checks import EDGE_REACH_OF_SCALE, check_description


@pytest.fixture(scope="module")
def description():
    return TalkingHeadSource(176, 144, seed=0).description


def _raised_by(description, share_of_scale: float):
    """The description with its model moved up until its top vertex lies `share_of_scale`
    of its scale above the texture's top edge."""
    params = np.array(description.params, dtype=np.float64)
    top_px = float(description.projected()[:, 1].min())
    params[1] -= top_px + share_of_scale * params[2]
    return replace(description, params=params)


def test_a_face_cut_by_the_edge_passes(description):
    check_description(description)
    # foreman: the forehead above the picture (86 % of vertices inside the texture).
    check_description(_raised_by(description, 0.5 * EDGE_REACH_OF_SCALE))


def test_a_model_far_off_its_texture_is_refused(description):
    with pytest.raises(FaceError, match=r"d\.face: the model lies outside its texture"):
        check_description(_raised_by(description, 1.0), where="d.face")
