"""`uma.bench.mbc_clips.check_clip`: what the bench cannot score is one line, before tracking."""

import numpy as np
import pytest

from uma.bench.mbc_clips import ClipSpec, check_clip, check_first_frame
from uma.errors import FaceError, VideoError


@pytest.fixture(scope="module")
def description():
    from uma.face.talking_head import astronaut_description

    return astronaut_description(176, 144)  # its texture: the whole 176x144 picture


def _clip(description, count, width=176, height=144):
    frames = [np.full((height * 3 // 2, width), 128, np.uint8) for _ in range(count)]
    return ClipSpec("clip", frames, 25.0, description, None, "clip.mp4")


def test_a_clip_of_one_frame_is_refused(description):
    # it was scored as PSNR 0.0 everywhere: frame 0 is the reference, no frame was scored
    with pytest.raises(VideoError, match=r"clip\.mp4: holds 1 frame\(s\): expected at least 2"):
        check_clip(_clip(description, 1), "a.face")
    check_clip(_clip(description, 2), "a.face")


def test_a_description_from_a_larger_clip_is_refused(description):
    with pytest.raises(FaceError, match=r"a\.face: its texture reaches to x 176, y 144, past clip"):
        check_clip(_clip(description, 2, 88, 72), "a.face")


def test_an_odd_sized_clip_cropped_by_one_pixel_keeps_its_description(description):
    from dataclasses import replace

    odd = replace(description, texture=description.texture[:143])  # cut from a 176x143 frame
    check_clip(_clip(odd, 2, 176, 142), "a.face")  # the clip's 143 rows are read as 142


def test_a_clip_opening_on_a_blank_picture_is_refused(description):
    import cv2

    face = cv2.cvtColor(description.texture, cv2.COLOR_BGR2YUV_I420)
    check_first_frame(ClipSpec("clip", [face, face], 25.0, description, None, "clip.mp4"))
    # 10 black frames, then the face: the bench drew the face over grey and scored 49 dB
    black = np.zeros_like(face)
    black[face.shape[0] * 2 // 3 :] = 128
    late = ClipSpec("clip", [black, face], 25.0, description, None, "clip.mp4")
    with pytest.raises(VideoError, match=r"clip\.mp4: frame 0: image is flat: nothing to fit: exp"):
        check_first_frame(late)


def test_a_textured_opening_runs_on_even_without_a_face(description):
    # a picture the tracker may not find the face in is not refused: the bench runs on from
    # the description's picture and says so (test_bench_mbc)
    noise = np.random.default_rng(0).integers(0, 256, (216, 176), dtype=np.uint8)
    check_first_frame(ClipSpec("clip", [noise, noise], 25.0, description, None, "clip.mp4"))
