"""The model path's shortcuts draw and decide what the long way does: the engine's block map
without a picture when it cannot pay for a change, the face mask without the picture, the torso
kept from one frame to the next."""

from __future__ import annotations

import numpy as np
import pytest

from uma.mbc.block_map import BlockMap

SIZE = (176, 144)


def _face(x0: int, y0: int, side: int = 48) -> np.ndarray:
    face = np.zeros(SIZE[::-1], bool)
    face[y0 : y0 + side, x0 : x0 + side] = True
    return face


def _maps_after(frames, hold_when_broke: bool):
    """A map stepped by the engine over `frames` (rendering, face, source, stream bits); with
    `hold_when_broke`, a frame whose allowance cannot pay for a change is held instead."""
    block_map, held = BlockMap(SIZE, 25.0), 0
    plate_known = np.ones(SIZE[::-1], bool)
    plate_known[:, :40] = False
    for shown, face, source, stream_bits in frames:
        if hold_when_broke and block_map.broke(stream_bits):
            block_map.hold(face, stream_bits, plate_known)
            held += 1
        else:
            plate, reference = np.roll(shown, 3, axis=1), np.roll(shown, -2, axis=0)
            block_map.step(shown, face, plate, reference, source, stream_bits, plate_known,
                           compose=False)  # fmt: skip
        yield block_map, held


def test_a_held_frame_moves_the_map_as_a_choice_with_nothing_to_spend() -> None:
    rng = np.random.default_rng(5)
    width, height = SIZE
    frames = []
    for k in range(40):
        shown = rng.integers(0, 256, (height * 3 // 2, width), dtype=np.uint8)
        source = rng.integers(0, 256, (height, width), dtype=np.uint8)
        # The face wanders (blocks go stale or leave the window) and sometimes leaves.
        face = _face(40 + 3 * k % 60, 30 + k % 20) if k % 13 != 12 else np.zeros_like(_face(0, 0))
        frames.append((shown, face, source, 60.0 + 30.0 * (k % 3)))
    held_total = 0
    for (long, _), (short, held) in zip(
        _maps_after(frames, False), _maps_after(frames, True), strict=True
    ):
        assert np.array_equal(long.state, short.state)
        assert np.array_equal(long.sent, short.sent)
        assert (long.bits, long.changes, long.bucket) == (short.bits, short.changes, short.bucket)
        held_total = held
    assert 5 < held_total < 35  # both kinds of frame were met


@pytest.fixture(scope="module")
def moved(head):
    """A layered renderer on the talking head's frame 0 and three sets to draw."""
    import cv2

    from uma.mbc.scene_render import SceneRenderer

    def renderer():
        out = SceneRenderer(head.description, (352, 288), soften_outline=True)
        out.set_reference(cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420),
                          head.params_at(0))  # fmt: skip
        return out

    sets = []
    for k, body in ((4, (3.0, -2.0, 0.01)), (8, (0.0, 0.0, 0.0)), (10, (-1.5, 1.0, -0.02))):
        params = head.params_at(k).copy()
        params[0] += k / 2
        sets.append((params, (1.05, -2.0), np.array(body)))
    return renderer, sets


def test_the_face_mask_is_the_rendered_face(moved) -> None:
    renderer, sets = moved
    drawn = renderer()
    for params, light, body in sets:
        assert np.array_equal(drawn.face_mask(params, light, body),
                              drawn.render(params, light, body)[1])  # fmt: skip


def test_the_kept_torso_draws_what_a_fresh_renderer_draws(moved) -> None:
    renderer, sets = moved
    kept = renderer()
    order = [0, 0, 1, 0, 2, 2, 1]  # the same body again, another, and back
    for k, luma_only in zip(order, [True, False, False, True, False, True, False], strict=True):
        params, light, body = sets[k]
        kept._memo.clear()  # draw every time (the memo would hand back the last picture)
        got, face = kept.render(params, light, body, luma_only=luma_only)
        want, want_face = renderer().render(params, light, body, luma_only=luma_only)
        assert np.array_equal(face, want_face)
        assert np.array_equal(got[:288], want[:288])
        if not luma_only:
            assert np.array_equal(got, want)


def test_a_luma_only_mirror_draws_and_learns_the_receivers_luma(moved, head) -> None:
    """The engine's luma-only mirror against a full receiver through refreshes (a box pasted
    on each one's own drawing, the plate learning it, the camera moving the plate) and the
    description's face: every drawing's luma and face, and the plate's luma, the same."""
    import cv2

    renderer, sets = moved
    full, mirror = renderer(), renderer()
    mirror.set_luma_only()
    mirror.set_reference(full.reference, full.reference_params)  # its first one, luma only
    full.set_reference(full.reference, full.reference_params)
    for step, k in enumerate((5, 9, 11)):
        params, light, body = sets[step]
        frame = cv2.cvtColor(head.render_bgr(k), cv2.COLOR_BGR2YUV_I420)
        fresh = np.zeros((288, 352), bool)
        fresh[40 + 8 * step : 200, 100 : 260 - 10 * step] = True
        for drawn in (full, mirror):
            picture = drawn.render(params, light, body)[0].copy()
            picture[:288][fresh] = frame[:288][fresh]
            drawn.set_reference(picture, params, fresh, np.array([1.0 * step, -0.5]))
            drawn.set_face_source(step == 1)
        for params, light, body in sets:
            want, want_face = full.render(params, light, body)
            for _ in range(2):  # drawn, then from the memo
                got, face = mirror.render(params, light, body)
                assert np.array_equal(got[:288], want[:288])
                assert np.array_equal(face, want_face)
        assert np.array_equal(mirror.plate.picture[:288], full.plate.picture[:288])
        assert np.array_equal(mirror.plate.known, full.plate.known)
    assert not np.array_equal(mirror.plate.picture[288:], full.plate.picture[288:])


def test_the_outline_box_from_the_mask_is_the_box_of_its_pixels() -> None:
    """`soften_outline` takes the person's box from the mask itself (no list of its pixels):
    the same rectangle as from `findNonZero`'s pixels, and empty for an empty mask."""
    import cv2

    rng = np.random.default_rng(11)
    for _ in range(50):
        height, width = rng.integers(1, 120, 2)
        mask = np.zeros((height, width), np.uint8)
        for _ in range(rng.integers(0, 4)):
            y, x = rng.integers(0, height), rng.integers(0, width)
            mask[y : y + rng.integers(1, 30), x : x + rng.integers(1, 30)] = 1
        points = cv2.findNonZero(mask)
        want = (0, 0, 0, 0) if points is None else cv2.boundingRect(points)
        assert cv2.boundingRect(mask) == want


def test_a_drawing_for_one_box_is_the_whole_drawing_there(moved) -> None:
    """A luma drawing for a caller reading one box (the engine's map: its window and its blurs'
    margin; boxes at the picture's edges and corners) has the whole drawing's luma in that box
    and its face mask everywhere, with the torso moved, turned or still and the outline soft."""
    from uma.mbc.block_map import BlockMap

    renderer, sets = moved
    whole, windowed = renderer(), renderer()
    block_map = BlockMap((352, 288), 25.0)
    boxes = [
        block_map.read_box,
        lambda face: (0, 0, 64, 48),
        lambda face: (300, 240, 352, 288),
        lambda face: (110, 60, 190, 150),
    ]
    for params, light, body in sets:
        want, want_face = whole.render(params, light, body, luma_only=True)
        for only in boxes:
            windowed._memo.clear()
            got, face = windowed.render(params, light, body, luma_only=True, only=only)
            assert np.array_equal(face, want_face)
            x0, y0, x1, y1 = only(want_face)
            assert np.array_equal(got[y0:y1, x0:x1], want[y0:y1, x0:x1])
        # Never kept: the next whole drawing is drawn whole.
        again, _ = windowed.render(params, light, body, luma_only=True)
        assert np.array_equal(again[:288], want[:288])


def test_a_drawing_for_one_box_keeps_the_whole_torso(moved) -> None:
    """A windowed luma drawing (the engine's map) keeps its torso layer whole: the next drawing
    with the same body motion, windowed or whole, takes it and draws what a fresh renderer
    draws; a box far from the torso (a corner) does not cut the kept layer."""
    renderer, sets = moved
    windowed, whole = renderer(), renderer()
    corner = lambda face: (0, 0, 64, 48)  # noqa: E731
    for params, light, body in sets:
        windowed._memo.clear()
        windowed.render(params, light, body, luma_only=True, only=corner)
        whole._memo.clear()
        want, _ = whole.render(params, light, body, luma_only=True)
        assert np.array_equal(windowed._torso_kept[2][:288], whole._torso_kept[2][:288])
        kept = windowed._torso_kept
        moved_params = params.copy()
        moved_params[0] += 1.0  # another head pose, the same body: the torso is taken
        windowed.render(moved_params, light, body, luma_only=True, only=corner)
        assert windowed._torso_kept is kept
        windowed._memo.clear()
        again, _ = windowed.render(params, light, body, luma_only=True)
        assert np.array_equal(again[:288], want[:288])
