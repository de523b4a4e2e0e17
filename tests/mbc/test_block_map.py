"""The block map beside the face's parameters (`uma.mbc.block_map`)."""

from __future__ import annotations

import numpy as np
import pytest

from uma.mbc.block_map import (
    BLOCK_PX,
    CHOICES,
    MAP_TOTAL_KBPS,
    BlockMap,
    change_bits,
    count_bits,
)

SIZE = (176, 144)
FPS = 25.0


def _picture(rng: np.random.Generator) -> np.ndarray:
    width, height = SIZE
    return rng.integers(0, 256, (height * 3 // 2, width), dtype=np.uint8)


def _face(x0: int = 64, y0: int = 48, side: int = 48) -> np.ndarray:
    width, height = SIZE
    face = np.zeros((height, width), bool)
    face[y0 : y0 + side, x0 : x0 + side] = True
    return face


def test_bits_of_a_count_and_a_change():
    assert [count_bits(n) for n in (0, 1, 2, 3, 6, 7)] == [1, 3, 3, 5, 5, 7]
    assert change_bits(256) == 8 + 2
    assert change_bits(121) == 7 + 2
    assert len(CHOICES) == 5


def test_the_engine_shows_the_plate_where_the_rendering_is_wrong():
    rng = np.random.default_rng(0)
    truth = _picture(rng)
    rendering = truth.copy()
    height = SIZE[1]
    # Three blocks beside the face drawn wrong; the plate holds them right.
    wrong = [(40, 48), (40, 56), (48, 112)]
    for y, x in wrong:
        rendering[y : y + BLOCK_PX, x : x + BLOCK_PX] = (
            255 - truth[y : y + BLOCK_PX, x : x + BLOCK_PX]
        )
    plate, reference = truth.copy(), _picture(rng)
    stream_bits = 60.0  # under the allowance: room for about two changes a frame
    engine = BlockMap(SIZE, FPS)
    shown = rendering
    for _ in range(4):
        shown = engine.step(rendering, _face(), plate, reference, truth[:height], stream_bits)
    for y, x in wrong:
        block = (slice(y, y + BLOCK_PX), slice(x, x + BLOCK_PX))
        before = np.abs(rendering[block].astype(int) - truth[block]).mean()
        after = np.abs(shown[block].astype(int) - truth[block]).mean()
        # An isolated block keeps about half the rendering at its edge (the feather): 0.6.
        assert after < 0.6 * before, (y, x, before, after)
    far = np.ones(SIZE[::-1], bool)
    for y, x in wrong:
        far[max(y - 16, 0) : y + BLOCK_PX + 16, max(x - 16, 0) : x + BLOCK_PX + 16] = False
    np.testing.assert_array_equal(shown[:height][far], rendering[:height][far])
    assert engine.changes == len(wrong)
    assert rendering[40, 48] != truth[40, 48]  # the rendering itself is never written


def test_an_exact_rendering_is_shown_as_drawn_and_costs_a_bit_a_frame():
    rng = np.random.default_rng(1)
    truth = _picture(rng)
    engine = BlockMap(SIZE, FPS)
    for _ in range(10):
        shown = engine.step(truth, _face(), _picture(rng), _picture(rng), truth[: SIZE[1]], 0.0)
        assert shown is truth
    assert engine.changes == 0 and engine.bits == 10


@pytest.mark.parametrize("stream_bits", [0.0, 70.0, 95.0, 140.0])
def test_the_stream_and_the_map_stay_under_the_total(stream_bits):
    rng = np.random.default_rng(2)
    engine = BlockMap(SIZE, FPS)
    frames = 200
    for _ in range(frames):
        truth, rendering = _picture(rng), _picture(rng)  # every block worth changing
        engine.step(rendering, _face(), _picture(rng), _picture(rng), truth[: SIZE[1]],
                    stream_bits)  # fmt: skip
    allowance = MAP_TOTAL_KBPS * 1000.0 / FPS * frames
    # At most the allowance plus the bucket's saving, and a bit a frame when the stream is over.
    assert engine.bits + stream_bits * frames <= max(allowance + 200.0, (stream_bits + 1) * frames)
    if stream_bits < 90.0:
        assert engine.changes > 0


def test_a_block_leaving_the_window_goes_back_to_the_rendering():
    rng = np.random.default_rng(3)
    truth = _picture(rng)
    rendering = truth.copy()
    rendering[0:BLOCK_PX, 0:BLOCK_PX] = 0
    plate = truth.copy()
    engine = BlockMap(SIZE, FPS)
    engine.step(rendering, _face(16, 16, 16), plate, truth, truth[: SIZE[1]], 0.0)
    assert engine.state[0, 0] != 0
    shown = engine.step(rendering, _face(120, 90, 16), plate, truth)  # the receiver's side
    assert engine.state[0, 0] == 0
    assert shown is rendering


def test_no_face_shows_the_rendering_and_clears_the_map():
    rng = np.random.default_rng(4)
    engine = BlockMap(SIZE, FPS)
    engine.state[3, 3] = 3
    rendering = _picture(rng)
    shown = engine.step(rendering, np.zeros(SIZE[::-1], bool), rendering, rendering)
    assert shown is rendering and not engine.state.any()


def test_a_picture_smaller_than_a_block_is_refused():
    with pytest.raises(ValueError, match="block map"):
        BlockMap((4, 4), FPS)


def test_the_face_never_takes_the_plate_the_reference_or_a_blur():
    rng = np.random.default_rng(5)
    truth = _picture(rng)
    height = SIZE[1]
    face = _face()
    rendering = truth.copy()
    rendering[:height][face] = 255 - truth[:height][face]  # the face drawn all wrong
    engine = BlockMap(SIZE, FPS)
    for _ in range(20):
        shown = engine.step(rendering, face, truth, truth, truth[:height], 0.0)
    # The plate and the reference hold the true face, yet the face's blocks stay as drawn.
    np.testing.assert_array_equal(shown[:height][face], rendering[:height][face])


def test_a_choice_ends_when_the_face_moves_away_from_where_it_was_taken():
    rng = np.random.default_rng(6)
    truth = _picture(rng)
    rendering = truth.copy()
    rendering[16:24, 16:24] = 0
    engine = BlockMap(SIZE, FPS)
    engine.step(rendering, _face(24, 24, 16), truth, truth, truth[: SIZE[1]], 0.0)
    assert engine.state[2, 2] != 0
    engine.step(rendering, _face(28, 24, 16), truth, truth)  # moved 4 px: kept
    assert engine.state[2, 2] != 0
    shown = engine.step(rendering, _face(36, 24, 16), truth, truth)  # 12 px: ended
    assert engine.state[2, 2] == 0 and shown is rendering


def test_a_block_on_the_outline_shows_the_plate_only_outside_the_face():
    rng = np.random.default_rng(7)
    truth = _picture(rng)
    height = SIZE[1]
    face = _face(64, 48, 48)
    face[44:48, 64:112] = True  # the face reaches 4 px into the row of blocks above it
    rendering = truth.copy()
    rendering[40:44, 64:112] = 255 - truth[40:44, 64:112]  # that row wrong outside the face
    plate = truth.copy()
    plate[:height][face] = 255 - truth[:height][face]  # the plate's guess over the face: wrong
    engine = BlockMap(SIZE, FPS)
    for _ in range(20):
        shown = engine.step(rendering, face, plate, plate, truth[:height], 0.0)
    assert (engine.state[5, 8:14] == CHOICES.index("plate")).all()
    np.testing.assert_array_equal(shown[44:48, 72:104], truth[44:48, 72:104])  # the face kept
    outside = np.abs(shown[40:44, 72:104].astype(int) - truth[40:44, 72:104]).mean()
    before = np.abs(rendering[40:44, 72:104].astype(int) - truth[40:44, 72:104]).mean()
    assert outside < 0.5 * before


def test_an_idle_frame_is_what_step_would_have_done_without_drawing():
    rng = np.random.default_rng(8)
    stepped, idled = BlockMap(SIZE, FPS), BlockMap(SIZE, FPS)
    idle_frames = 0
    for stream_bits in [200.0] * 6 + [0.0] * 6:  # over the allowance, then under it
        truth, rendering = _picture(rng), _picture(rng)
        args = (rendering, _face(), truth, truth, truth[: SIZE[1]], stream_bits)
        stepped.step(*args)
        if idled.idle(stream_bits):
            idle_frames += 1
        else:
            idled.step(*args)
        assert idled.bits == stepped.bits and idled.bucket == stepped.bucket
        np.testing.assert_array_equal(idled.state, stepped.state)
    assert 6 <= idle_frames < 12 and stepped.changes > 0  # owed bits paid back first
