import av
import numpy as np
import pytest

from uma.errors import VideoError
from uma.video.frame import read_frame


def _clip(path, frames=5, size=(64, 48)):
    """A tiny clip whose frame k is flat grey 40 + 30 k, so a frame's index shows in it."""
    width, height = size
    with av.open(str(path), "w", format="mp4") as container:
        stream = container.add_stream("libx264", rate=25)
        stream.width, stream.height, stream.pix_fmt = width, height, "yuv420p"
        stream.options = {"crf": "0"}
        for k in range(frames):
            picture = np.full((height, width, 3), 40 + 30 * k, np.uint8)
            frame = av.VideoFrame.from_ndarray(picture, format="bgr24")
            frame.pts = k
            container.mux(stream.encode(frame))
        container.mux(stream.encode(None))
    return path


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    return _clip(tmp_path_factory.mktemp("clip") / "grey.mp4")


@pytest.mark.parametrize("index", [0, 1, 4])
def test_reads_the_frame_asked_for(clip, index):
    frame = read_frame(clip, index)
    assert frame.shape == (48, 64, 3) and frame.dtype == np.uint8
    assert abs(float(frame.mean()) - (40 + 30 * index)) < 3


def test_past_the_end_names_the_count(clip):
    with pytest.raises(VideoError, match=r"grey\.mp4: frame 5 is past the end: .* 5 frames"):
        read_frame(clip, 5)


@pytest.mark.parametrize("index", [-1, 1.5, True])
def test_bad_index(clip, index):
    with pytest.raises(VideoError, match="whole number"):
        read_frame(clip, index)


def test_missing_file(tmp_path):
    with pytest.raises(VideoError, match="nope.mp4: no such video file"):
        read_frame(tmp_path / "nope.mp4", 0)


def test_not_a_video(tmp_path):
    text = tmp_path / "notes.mp4"
    text.write_text("not a video at all\n" * 50)
    with pytest.raises(VideoError, match="notes.mp4: not a video"):
        read_frame(text, 0)
    assert issubclass(VideoError, ValueError)


def test_real_clips_have_their_frame_counts(shared_data):
    video = shared_data / "faces" / "video"
    assert read_frame(video / "akiyo.mp4", 299).shape == (288, 352, 3)
    with pytest.raises(VideoError, match="300 frames"):
        read_frame(video / "akiyo.mp4", 300)
    assert read_frame(video / "carphone_qcif.mp4", 381).shape == (144, 176, 3)
