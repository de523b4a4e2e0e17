"""The face readers refuse what is no regular file in one line, before reading a byte."""

import os

import pytest

from uma.errors import FaceError
from uma.face.clip import read_picture
from uma.face.description_file import load_description
from uma.face.load import load_model


@pytest.mark.parametrize("reader", [read_picture, load_model, load_description])
def test_a_fifo_is_refused_without_blocking(tmp_path, reader):
    path = tmp_path / "face.yaml"
    os.mkfifo(path)
    with pytest.raises(FaceError, match="got a FIFO"):
        reader(path)


@pytest.mark.parametrize("reader", [read_picture, load_model, load_description])
def test_a_symlink_loop_is_one_line(tmp_path, reader):
    path = tmp_path / "face.png"
    path.symlink_to(path)
    with pytest.raises(FaceError, match="symlink loop"):
        reader(path)


def test_a_missing_picture_keeps_its_message(tmp_path):
    with pytest.raises(FaceError, match="no such image or video file"):
        read_picture(tmp_path / "none.png")
