"""The canvas a drawing codec starts from at the receiver with `CANVAS_WINDOW_S` set: the
largest full-frame picture of the last few seconds of source time, not the last one (a low
rung's keyframe just before a switch); with 0 (the default), the last one."""

import numpy as np
import pytest

from uma.codecs import full_frame_names, model_names
from uma.sim import coders
from uma.sim.coders import CanvasKeeper, CodecClock, ReceiverCoder
from uma.sim.context import CodecContext
from uma.sim.packets import EncodedUnit

FULL, MODEL = full_frame_names()[0], model_names()[0]
CIF, SQCIF = (352, 288), (128, 96)


def picture(size, value):
    width, height = size
    return np.full((height * 3 // 2, width), value, dtype=np.uint8)


class Shows:
    """A decoder that returns, for each unit, the picture the test put under its frame."""

    pictures: dict[int, np.ndarray] = {}

    def __init__(self, *, context=None):
        self.context = context

    def decode(self, unit):
        return {unit.frame: self.pictures[unit.frame]}


@pytest.fixture
def receiver(monkeypatch):
    monkeypatch.setattr(coders, "DECODERS", {FULL: Shows, MODEL: Shows})
    monkeypatch.setattr(coders, "CANVAS_WINDOW_S", 4.0)
    context = CodecContext(source_size=CIF, fps=25.0)
    return ReceiverCoder(context, clock=CodecClock(False))


def feed(receiver, frames_codecs):
    for seq, (frame, codec) in enumerate(frames_codecs):
        receiver.decode(EncodedUnit(seq, frame, codec, 0, *CIF, True, b"x"))


def test_model_draws_over_the_cif_picture_not_the_sqcif_keyframe_before_it(receiver):
    # CIF at frames 0..9, then the lowest rung (SQCIF) at 10..20, the model codec from 21.
    Shows.pictures = {f: picture(CIF, 200) for f in range(10)}
    Shows.pictures |= {f: picture(SQCIF, 50) for f in range(10, 21)}
    Shows.pictures[21] = picture(CIF, 0)
    feed(receiver, [(f, FULL) for f in range(21)] + [(21, MODEL)])
    background = receiver.context.background
    # The newest CIF picture (frame 9), 0.48 s before the switch: within the 4 s window.
    assert background is Shows.pictures[9]
    assert background.shape == (288 * 3 // 2, 352)


def test_an_old_cif_picture_gives_way_to_the_recent_small_one(receiver):
    # The CIF picture is 120 frames (4.8 s) older than the switch: beyond the window.
    Shows.pictures = {0: picture(CIF, 200), 100: picture(SQCIF, 50), 120: picture(CIF, 0)}
    feed(receiver, [(0, FULL), (100, FULL), (120, MODEL)])
    assert receiver.context.background is Shows.pictures[100]


def test_a_window_of_zero_keeps_the_last_picture(receiver, monkeypatch):
    monkeypatch.setattr(coders, "CANVAS_WINDOW_S", 0.0)
    receiver.canvases = CanvasKeeper(25.0)
    Shows.pictures = {0: picture(CIF, 200), 5: picture(SQCIF, 50), 6: picture(CIF, 0)}
    feed(receiver, [(0, FULL), (5, FULL), (6, MODEL)])
    assert receiver.context.background is Shows.pictures[5]


def test_the_keeper_keeps_the_newest_of_a_size_within_the_window():
    keeper = CanvasKeeper(25.0, window_s=4.0)
    keeper.add(0, picture(SQCIF, 1))
    keeper.add(10, picture(SQCIF, 2))
    assert keeper.pick(20, None)[0, 0] == 2  # the newest of the one size
    assert keeper.pick(200, "last") == "last"  # nothing within 100 frames of frame 200
