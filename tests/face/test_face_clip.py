"""Describing a frame of a video, and the shipped clip points (akiyo, carphone)."""

import cv2
import numpy as np
import pytest

from uma.cli import main
from uma.errors import FaceError
from uma.face import ContentDescription, load_description
from uma.face.clip import describe_clip, picture_of, read_picture
from uma.face.points import load_points
from uma.paths import codecs_dir

CLIPS = {"akiyo": ("akiyo.mp4", 0, (288, 352)), "carphone": ("carphone_qcif.mp4", 18, (144, 176))}


def test_describe_a_video_frame(astronaut_clip, tmp_path, capsys):
    points = codecs_dir() / "face" / "astronaut.yaml"
    code = main(
        [
            "describe",
            str(astronaut_clip),
            "--frame",
            "1",
            "--points",
            str(points),
            "--out",
            str(tmp_path),
        ]
    )
    assert code == 0, capsys.readouterr().err
    description = load_description(tmp_path / "astro.face")
    assert description.fit_rms_px < 2.0
    assert (tmp_path / "astro.fit.png").is_file()
    # The same frame as a still image gives the same fit.
    still = tmp_path / "astro.png"
    cv2.imwrite(str(still), read_picture(astronaut_clip, frame=1))
    assert main(["describe", str(still), "--points", str(points), "--out", str(tmp_path)]) == 0
    assert abs(load_description(tmp_path / "astro.face").fit_rms_px - description.fit_rms_px) < 1e-9


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--frame", "3"], "frame 3 is past the end: the video has 3 frames"),
        ([], "is a video: say which frame"),
        (["--frame", "-2"], "whole number >= 0"),
    ],
)
def test_bad_frames_are_one_line_and_exit_2(astronaut_clip, tmp_path, capsys, extra, message):
    points = codecs_dir() / "face" / "astronaut.yaml"
    args = [
        "describe",
        str(astronaut_clip),
        *extra,
        "--points",
        str(points),
        "--out",
        str(tmp_path),
    ]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("uma: error: ") and message in err[0]
    assert "astro.mp4" in err[0]
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    "name, content, message",
    [
        ("nope.mp4", None, "nope.mp4: no such image or video file"),
        ("notes.mp4", b"plain text, no video\n" * 40, "neither an image OpenCV reads nor a video"),
        ("empty.avi", b"", "neither an image OpenCV reads nor a video"),
    ],
)
def test_bad_inputs_are_one_line_and_exit_2(tmp_path, capsys, name, content, message):
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    points = codecs_dir() / "face" / "astronaut.yaml"
    out = tmp_path / "out"
    args = ["describe", str(path), "--frame", "0", "--points", str(points), "--out", str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert not out.exists()


def test_frame_on_a_still_is_refused(tmp_path, capsys):
    still = tmp_path / "a.png"
    cv2.imwrite(str(still), np.zeros((20, 20, 3), np.uint8))
    points = codecs_dir() / "face" / "astronaut.yaml"
    assert main(["describe", str(still), "--frame", "2", "--points", str(points)]) == 2
    assert "--frame is for videos" in capsys.readouterr().err


@pytest.mark.parametrize(
    "text, message",
    [
        ("video: 3\npoints: {'3.5': [1, 2]}\n", r"p.yaml:1 \(video\): expected a path"),
        (
            "video: a.mp4\nframe: -1\npoints: {'3.5': [1, 2]}\n",
            r"p.yaml:2 \(frame\): expected a whole number",
        ),
        (
            "image: a.png\nframe: 2\npoints: {'3.5': [1, 2]}\n",
            r":2 \(frame\): a frame is of a video",
        ),
        ("video: a.mp4\nimage: b.png\npoints: {'3.5': [1, 2]}\n", "not both"),
    ],
)
def test_bad_points_file_keys(tmp_path, text, message):
    path = tmp_path / "p.yaml"
    path.write_text(text)
    with pytest.raises(FaceError, match=message):
        load_points(path)


def test_frame_without_video_waits_for_the_command_line(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text("frame: 2\npoints: {'3.5': [1, 2]}\n")
    points = load_points(path)
    assert points.frame == 2 and points.video is None
    with pytest.raises(FaceError, match="no video: names the clip"):
        picture_of(points)


def test_shipped_points_name_their_clips(shared_data):
    for clip, (video, frame, _) in CLIPS.items():
        points = load_points(codecs_dir() / "face" / f"{clip}.yaml")
        assert points.video == shared_data / "faces" / "video" / video
        assert points.frame == frame and len(points.points) == 30
    astronaut = load_points(codecs_dir() / "face" / "astronaut.yaml")
    assert astronaut.image == "skimage:astronaut" and astronaut.video is None


@pytest.mark.parametrize("clip", sorted(CLIPS))
def test_describe_clip_fits_the_real_clips(shared_data, clip):
    description = describe_clip(codecs_dir() / "face" / f"{clip}.yaml")
    assert isinstance(description, ContentDescription)
    # Hand clicks on a real face: about a pixel, well under the 6 %-of-scale plausibility limit.
    assert 0.3 < description.fit_rms_px < 2.0
    height, width = CLIPS[clip][2]
    x0, y0 = description.origin_px
    assert 0 <= x0 < width and 0 <= y0 < height
    # Frontal-ish frames: the head within 25 deg of frontal on every axis.
    assert np.all(np.abs(description.params[3:6]) < 0.45)


@pytest.mark.parametrize("clip", sorted(CLIPS))
def test_cli_describes_the_real_clips(shared_data, tmp_path, capsys, clip):
    points = codecs_dir() / "face" / f"{clip}.yaml"
    assert main(["describe", "--points", str(points), "--out", str(tmp_path)]) == 0
    video, frame, _ = CLIPS[clip]
    stem = video.removesuffix(".mp4")
    out = capsys.readouterr().out
    assert f"{stem}.face" in out and "px rms" in out
    assert load_description(tmp_path / f"{stem}.face").fit_rms_px < 2.0
    # The clip named explicitly, with its frame, gives the same description.
    explicit = shared_data / "faces" / "video" / video
    args = ["describe", str(explicit), "--frame", str(frame), "--points", str(points)]
    assert main([*args, "--out", str(tmp_path / "again")]) == 0
    assert (tmp_path / "again" / f"{stem}.face").read_bytes() == (
        tmp_path / f"{stem}.face"
    ).read_bytes()


def test_describe_clip_of_the_astronaut_photograph():
    description = describe_clip(codecs_dir() / "face" / "astronaut.yaml")
    assert abs(description.fit_rms_px - 1.47) < 0.02  # as the README quotes


def test_shipped_points_and_whole_frame_texture(shared_data):
    from uma.face import shipped_points

    assert shipped_points("akiyo").name == "akiyo.yaml"
    with pytest.raises(FaceError, match="expected one of akiyo"):
        shipped_points("foreman")
    cropped = describe_clip(shipped_points("carphone"))
    whole = describe_clip(shipped_points("carphone"), crop=False)
    assert whole.texture.shape == (144, 176, 3) and whole.origin_px == (0.0, 0.0)
    x0, y0 = cropped.origin_px
    assert np.allclose(whole.params[:2], cropped.params[:2] + [x0, y0])
    assert np.allclose(whole.params[2:], cropped.params[2:])
    assert np.allclose(whole.projected() - [x0, y0], cropped.projected())


def test_a_stronger_ridge_keeps_coefficients_moderate(shared_data):
    from uma.face import shipped_points

    default = describe_clip(shipped_points("carphone"))
    ridged = describe_clip(shipped_points("carphone"), ridge_px=2.0)
    assert np.abs(ridged.params[6:]).max() < np.abs(default.params[6:]).max()
    assert np.abs(ridged.shape).max() < np.abs(default.shape).max()
    assert ridged.fit_rms_px < default.fit_rms_px + 0.2
