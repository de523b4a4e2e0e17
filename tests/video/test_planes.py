"""Pictures in and out of PyAV frames by their planes give PyAV's own conversion's bytes."""

import av
import numpy as np
import pytest

from uma.video.planes import from_video_frame, to_video_frame


def _planes(frame) -> list[np.ndarray]:
    out = []
    for plane in frame.planes:
        rows = np.frombuffer(plane, dtype=np.uint8).reshape(-1, plane.line_size)
        out.append(rows[:, : plane.width].copy())
    return out


@pytest.mark.parametrize("width,height", [(352, 288), (176, 144), (174, 142), (130, 66), (2, 2)])
def test_planes_in_and_out_are_pyavs_own_conversion(width, height):
    picture = np.random.default_rng(width).integers(0, 256, (height * 3 // 2, width), np.uint8)
    theirs = av.VideoFrame.from_ndarray(picture, format="yuv420p")
    ours = to_video_frame(picture)
    assert all(np.array_equal(a, b) for a, b in zip(_planes(ours), _planes(theirs), strict=True))
    back = from_video_frame(theirs)
    assert np.array_equal(back, theirs.to_ndarray(format="yuv420p"))
    assert np.array_equal(from_video_frame(ours), picture) and back.flags.c_contiguous


def test_a_frame_in_another_format_takes_pyavs_path():
    picture = np.random.default_rng(0).integers(0, 256, (48, 64, 3), np.uint8)
    frame = av.VideoFrame.from_ndarray(picture, format="bgr24")
    assert np.array_equal(from_video_frame(frame), frame.to_ndarray(format="yuv420p"))


def test_a_strided_picture_is_copied_as_it_reads():
    wide = np.random.default_rng(1).integers(0, 256, (216, 360), np.uint8)
    picture = wide[:, :176]  # not contiguous
    assert np.array_equal(from_video_frame(to_video_frame(picture)), picture)
