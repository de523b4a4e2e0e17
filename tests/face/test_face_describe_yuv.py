"""`uma describe` on raw YUV (--size) and on a face the picture's edge cuts (foreman)."""

from __future__ import annotations

from uma.cli import main
from uma.face import load_description
from uma.mbc.checks import check_description
from uma.paths import codecs_dir

FOREMAN = ("faces", "video", "foreman_part_qcif.yuv")


def test_describe_reads_raw_yuv_with_a_face_cut_by_the_edge(shared_data, tmp_path, capsys):
    clip = shared_data.joinpath(*FOREMAN)
    points = codecs_dir() / "face" / "foreman.yaml"
    args = ["describe", str(clip), "--size", "176x144", "--points", str(points)]
    assert main([*args, "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "1.2" in out and "cuts" in err  # fitted to 1.22 px rms; no detected face, warned
    description = load_description(tmp_path / "foreman_part_qcif.face")
    check_description(description, where="foreman")  # the codec takes it (86 % inside)
    assert description.head_ring_outlines == 1.05  # the sender's ring, from the first second


def test_raw_yuv_without_its_size_is_one_line(tmp_path, capsys):
    clip = tmp_path / "clip.yuv"
    clip.write_bytes(bytes(176 * 144 * 3 // 2))
    points = codecs_dir() / "face" / "foreman.yaml"
    assert main(["describe", str(clip), "--points", str(points), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "clip.yuv" in err and "--size" in err
    assert main(["describe", str(clip), "--size", "17x9", "--points", str(points)]) == 2
    assert main(["describe", str(clip), "--size", "176x144", "--frame", "3", "--points",
                 str(points), "--out", str(tmp_path)]) == 2  # fmt: skip
    assert "past the clip's end (1 frames)" in capsys.readouterr().err


def test_a_points_file_naming_a_raw_clip_is_read_with_size(shared_data, tmp_path, capsys):
    import yaml

    # was "neither an image OpenCV reads nor a video PyAV decodes": video: was read as a video
    shipped = yaml.safe_load((codecs_dir() / "face" / "foreman.yaml").read_text())
    own = {"video": str(shared_data.joinpath(*FOREMAN)), "frame": 0, "points": shipped["points"]}
    points = tmp_path / "foreman.yaml"
    points.write_text(yaml.safe_dump(own))
    args = ["describe", "--points", str(points), "--size", "176x144", "--out", str(tmp_path)]
    assert main(args) == 0
    assert (tmp_path / "foreman_part_qcif.face").is_file()
    capsys.readouterr()
    assert main(args[:3] + args[5:]) == 2  # without --size: one line asking for it
    assert "foreman_part_qcif.yuv: a raw YUV clip: expected --size" in capsys.readouterr().err
