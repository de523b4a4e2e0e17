"""Face boxes of a source's frames: ground truth for the talking head, none for the pattern."""

import numpy as np

from uma.face import TalkingHeadSource
from uma.face.region import FaceBoxes, face_mode, points_box
from uma.video import PatternSource


def test_talking_head_box_contains_its_projected_points():
    source = TalkingHeadSource(width=176, height=144, seed=3, frame_count=12)
    boxes = FaceBoxes(source)
    frames = list(boxes.wrap(source.frames()))
    assert len(boxes.boxes) == len(frames) == 12
    assert boxes.mode == "truth"
    for index, box in enumerate(boxes.boxes):
        points = source.ground_truth(index)["points"]
        inside = points[
            (points[:, 0] >= 0) & (points[:, 0] < 176) & (points[:, 1] >= 0) & (points[:, 1] < 144)
        ]
        assert box is not None
        assert np.all(inside[:, 0] >= box.x) and np.all(inside[:, 0] <= box.x + box.width)
        assert np.all(inside[:, 1] >= box.y) and np.all(inside[:, 1] <= box.y + box.height)
        # a small margin, not the whole frame
        assert box.width * box.height < 0.9 * 176 * 144


def test_points_box_adds_a_margin_and_clips_to_the_frame():
    box = points_box(np.array([[10.0, 20.0], [30.0, 60.0]]), 100, 100, margin=0.1)
    assert (box.x, box.y) == (8, 16)
    assert box.x + box.width >= 32 and box.y + box.height >= 64
    edge = points_box(np.array([[-5.0, -5.0], [99.0, 99.0]]), 100, 100)
    assert (edge.x, edge.y, edge.x + edge.width, edge.y + edge.height) == (0, 0, 100, 100)


def test_pattern_source_has_no_face_box():
    source = PatternSource(64, 48, 25, seed=0, frame_count=3)
    boxes = FaceBoxes(source)
    list(boxes.wrap(source.frames()))
    assert face_mode(source) == "none" and boxes.boxes == [None, None, None]


class _Clip:
    """A looped 'file' clip of two frames: a face-like frame that the detector may miss."""

    name, width, height, clip_frames = "clip.y4m", 64, 48, 2


def test_detection_is_cached_by_clip_frame_and_falls_back_to_the_last_box(monkeypatch):
    import uma.face.detect as detect
    from uma.failure import Failure

    calls = []

    def fake_detect(gray):
        calls.append(int(gray[0, 0]))
        return detect.Box(1, 2, 30, 30) if gray[0, 0] == 1 else Failure("no face detected")

    monkeypatch.setattr(detect, "detect_face", fake_detect)
    frames = [np.full((72, 64), v, np.uint8) for v in (2, 1, 2, 1, 2)]  # looped: 0 1 0 1 0
    boxes = FaceBoxes(_Clip())
    list(boxes.wrap(frames))
    assert calls == [2, 1]  # once per distinct clip frame
    assert boxes.boxes[0] is None  # no face found yet
    assert boxes.boxes[1:] == [detect.Box(1, 2, 30, 30)] * 4


def test_the_cascade_answers_a_picture_it_has_seen_from_memory(monkeypatch):
    import uma.face.detect as detect

    frame = next(iter(TalkingHeadSource(width=176, height=144, seed=0, frame_count=1).frames()))
    luma = np.ascontiguousarray(frame[:144])
    first = detect.detect_face(luma)
    assert first  # the talking head's face is found
    calls = []
    real = detect._cascade

    def counting():
        calls.append(1)
        return real()

    monkeypatch.setattr(detect, "_cascade", counting)
    again = detect.detect_face(luma.copy())
    assert again == first and calls == []  # the same picture: no second detection
    shifted = np.roll(luma, 1, axis=1)
    detect.detect_face(shifted)
    assert calls == [1]  # another picture is detected afresh
    found = detect.detect_faces(luma)
    found.clear()  # a caller's list is its own
    assert detect.detect_faces(luma) == [first]


def _plain_points_box(points, width, height, margin=0.1):
    """`points_box` as it was (session mbc12 took Python floats): numpy scalars throughout."""
    from uma.face.detect import Box

    points = np.asarray(points, dtype=np.float64)
    points = points[np.all(np.isfinite(points), axis=1)]
    if points.size == 0:
        return None
    x0, y0 = points.min(axis=0)
    x1, y1 = points.max(axis=0)
    dx, dy = margin * (x1 - x0), margin * (y1 - y0)
    left, top = max(0, int(np.floor(x0 - dx))), max(0, int(np.floor(y0 - dy)))
    right, bottom = min(width, int(np.ceil(x1 + dx)) + 1), min(height, int(np.ceil(y1 + dy)) + 1)
    if right <= left or bottom <= top:
        return None
    return Box(left, top, right - left, bottom - top)


def test_points_box_is_the_plain_one_on_any_points() -> None:
    rng = np.random.default_rng(8)
    seen = set()
    for k in range(400):
        points = rng.normal(150, 80, (90, 2)) * (1e-3, 1.0, 10.0)[k % 3]
        if k % 7 == 0:
            points[rng.integers(0, 90, 5)] = np.nan
        if k % 11 == 0:
            points[:] = np.inf
        margin = 0.1 * (k % 3)
        got = points_box(points, 352, 288, margin=margin)
        assert got == _plain_points_box(points, 352, 288, margin)
        seen.add(got is None)
    assert seen == {True, False}
