"""The model path's exact cuts (session mbc12) give what the plain way gives, to the bit: the
face's luma from one projection, the receiver's block map when it holds nothing, the light
read through the mask."""

from __future__ import annotations

import numpy as np
import pytest


def _plain_face_luma(renderer, params):
    """`SceneRenderer.face_luma` as it was: the model projected for the box, again for the
    triangles facing the camera, and the face source's pose projected on every call."""
    import cv2

    from uma.face.geometry import project, visible_triangles
    from uma.face.render import barycentric_affine, triangle_labels
    from uma.mbc.layered_kernels import FAR_OUTSIDE_MAP, triangle_maps

    model = renderer.description.model
    width, height = renderer.size
    target = project(model, params)
    x0, y0 = np.maximum(np.floor(target.min(axis=0)).astype(int), 0)
    x1 = min(int(np.ceil(target[:, 0].max())) + 1, width)
    y1 = min(int(np.ceil(target[:, 1].max())) + 1, height)
    if x1 <= x0 or y1 <= y0:
        return np.zeros((0, 0), np.uint8), np.zeros((0, 0), bool), (0, 0)
    local = target - (x0, y0)
    triangles = model.triangles
    labels = triangle_labels(
        local, triangles, (y1 - y0, x1 - x0), triangle_mask=visible_triangles(model, params)
    )
    picture, source = renderer.reference, renderer._reference_points[: model.n_vertices]
    if renderer._face_source is not None:
        picture = renderer._face_source[0]
        source = project(model, renderer._face_source[1])
    maps = np.matmul(source[triangles].transpose(0, 2, 1), barycentric_affine(local, triangles))
    xs, ys = renderer._x[: y1 - y0, : x1 - x0], renderer._y[: y1 - y0, : x1 - x0]
    map_x, map_y = triangle_maps(labels, maps, FAR_OUTSIDE_MAP, xs, ys)
    patch = cv2.remap(
        picture[:height], map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
    )
    return patch, labels >= 0, (int(x0), int(y0))


@pytest.fixture(scope="module")
def scene(head):
    """A layered renderer on the talking head's frame 0, its frame 6 and poses to draw."""
    import cv2

    from uma.mbc.scene_render import SceneRenderer

    renderer = SceneRenderer(head.description, (352, 288))
    renderer.set_reference(cv2.cvtColor(head.render_bgr(0), cv2.COLOR_BGR2YUV_I420),
                           head.params_at(0))  # fmt: skip
    later = cv2.cvtColor(head.render_bgr(6), cv2.COLOR_BGR2YUV_I420)
    poses = []
    for k in (2, 5, 9):
        params = head.params_at(k).copy()
        params[0] += k / 3
        params[4] += 0.05 * (k - 5)
        poses.append(params)
    far = head.params_at(3).copy()
    far[0] = -500.0  # the face wholly outside the picture
    return renderer, later, head.params_at(6), poses + [far]


def test_the_face_luma_from_one_projection_is_the_plain_one(scene) -> None:
    renderer, later, later_params, poses = scene
    drawn = 0
    # The reference's face, the description's, a new reference, the description's again.
    for use_description, reference in ((False, None), (True, None), (False, later), (True, None)):
        if reference is not None:
            renderer.set_reference(reference, later_params)
        renderer.set_face_source(use_description)
        for params in poses + poses[:1]:  # the corners kept from the first call
            fast = renderer.face_luma(params)
            plain = _plain_face_luma(renderer, params)
            assert fast[2] == plain[2]
            assert np.array_equal(fast[0], plain[0]) and np.array_equal(fast[1], plain[1])
            drawn += fast[0].size > 0
    assert drawn == 16  # every pose but the one outside the picture drew a face


def test_the_face_pasted_on_a_drawing_reuses_its_projection(head, scene) -> None:
    """A receiver drawing with the description's face pastes it from the layered drawing's
    projection of the same frame: the same picture as projecting again."""
    from uma.mbc.scene_render import SceneRenderer

    _, later, later_params, poses = scene
    renderer, plain = (SceneRenderer(head.description, (352, 288)) for _ in range(2))
    plain.kept_points = lambda params: None  # the face projected on its own every time
    for each in (renderer, plain):
        each.set_reference(later, later_params)
        each.set_face_source(True)
    for params in poses[:3]:
        got, got_face = renderer.render(params, (1.1, -3.0))
        assert renderer.kept_points(params) is renderer.scene_points(params)
        assert np.array_equal(renderer.kept_points(params), renderer.scene.points(params))
        want, want_face = plain.render(params, (1.1, -3.0))
        assert np.array_equal(got, want) and np.array_equal(got_face, want_face)
    assert renderer.kept_points(poses[3]) is None


def test_the_receivers_map_holding_nothing_shows_what_the_long_way_shows() -> None:
    """The engine's map (always the long way: it chooses against the source) and a receiver
    taking its changes agree on every frame: the picture shown, the state and the bits;
    the receiver's frames with nothing held and nothing taken go the short way."""
    from uma.mbc.block_map import BlockMap

    width, height = 176, 144
    rng = np.random.default_rng(11)
    engine, receiver = BlockMap((width, height), 25.0), BlockMap((width, height), 25.0)
    known = np.ones((height, width), bool)
    known[:, :40] = False
    short = 0
    for k in range(60):
        shown = rng.integers(0, 256, (height * 3 // 2, width), dtype=np.uint8)
        source = rng.integers(0, 256, (height, width), dtype=np.uint8)
        plate, reference = np.roll(shown, 3, axis=1), np.roll(shown, -2, axis=0)
        face = np.zeros((height, width), bool)
        if k % 17 != 16:  # the face jumps now and then (choices go stale) and leaves once
            x0, y0 = 40 + (k // 5) * 11 % 70, 30 + k % 20
            face[y0 : y0 + 48, x0 : x0 + 48] = True
        stream_bits = 20.0 + 300.0 * (k % 9 == 0) + 10.0 * (k % 3)
        want = engine.step(shown, face, plate, reference, source, stream_bits, known)
        short += not receiver.state.any() and not len(engine.sent) and face.any()
        got = receiver.step(shown, face, plate, reference, None, stream_bits, known, engine.sent)
        assert np.array_equal(got, want)
        assert np.array_equal(receiver.state, engine.state)
        assert (receiver.bits, receiver.changes) == (engine.bits, engine.changes)
    assert 5 < short < 55 and engine.changes > 5  # both ways were met


def _plain_light(rendered, actual, mask, every=3):
    """`estimate_light` as it was: the mask's rows and columns, each mean taken again."""
    from uma.mbc.light import NEUTRAL_LIGHT
    from uma.mbc.scene_render import LIGHT_GAIN_RANGE, LIGHT_OFFSET_RANGE

    ys, xs = np.nonzero(mask)
    ys, xs = ys[::every], xs[::every]
    if ys.size < 64:
        return NEUTRAL_LIGHT
    r = rendered[ys, xs].astype(np.float64)
    a = actual[ys, xs].astype(np.float64)
    spread = r.std()
    if not np.isfinite(spread) or spread < 2.0:
        return NEUTRAL_LIGHT
    gain = float(np.mean((r - r.mean()) * (a - a.mean())) / spread**2)
    gain = float(np.clip(gain, *LIGHT_GAIN_RANGE))
    offset = float(np.clip(a.mean() - gain * r.mean(), *LIGHT_OFFSET_RANGE))
    return gain, offset


def test_the_light_read_through_the_mask_is_the_plain_one() -> None:
    from uma.mbc.light import estimate_light

    rng = np.random.default_rng(4)
    frame = rng.integers(0, 256, (288, 352), dtype=np.uint8)
    kinds = set()
    for k in range(40):
        h, w = 20 + 7 * k % 90, 30 + 5 * k % 80
        rendered = rng.integers(0, 256, (h, w), dtype=np.uint8)
        if k % 5 == 0:
            rendered[:] = 100 + (k % 3)  # flat: neutral
        gain, offset = 0.2 + 0.15 * (k % 30), -150.0 + 10.0 * k
        noisy = gain * rendered + offset + rng.normal(0, 3, (h, w))
        y0, x0 = 3 * k, 2 * k
        frame[y0 : y0 + h, x0 : x0 + w] = np.clip(noisy, 0, 255)
        actual = frame[y0 : y0 + h, x0 : x0 + w]  # a view into the frame, as the encoder's
        mask = rng.random((h, w)) < (0.02 if k % 7 == 0 else 0.7)
        for every in (1, 3):
            got = estimate_light(rendered, actual, mask, every=every)
            assert got == _plain_light(rendered, actual, mask, every)
            kinds.add("neutral" if got == (1.0, 0.0) else "clipped" if got[0] in (0.25, 4.0)
                      else "fitted")  # fmt: skip
    assert kinds == {"neutral", "clipped", "fitted"}
    with pytest.raises(ValueError, match="shape"):
        estimate_light(rendered, actual[1:], mask)


def test_the_tracker_projecting_the_prediction_once_tracks_as_the_plain_way(head, head_frames):
    """The prediction projected once for the share inside and the step's crop, the template's
    face width kept: the same poses, scores and work as projecting each time."""
    from uma.face.geometry import project
    from uma.mbc import FaceTracker

    class Plain(FaceTracker):
        def _inside(self, params, shape, points=None):
            return super()._inside(params, shape)

        def step(self, image, prediction, last_good=None, thresholds=None, *, points=None):
            return super().step(image, prediction, last_good, thresholds)

    fast, plain = FaceTracker(head.description, rng=0), Plain(head.description, rng=0)
    tracked = 0
    for frame, gray in enumerate(head_frames[:8]):
        got, want = fast.track(gray, frame=frame), plain.track(gray, frame=frame)
        assert (got.reason, got.evaluations, got.score) == (want.reason, want.evaluations,
                                                           want.score)  # fmt: skip
        assert np.array_equal(got.params, want.params)
        tracked += got.reason == "tracked"
    assert tracked >= 6
    template = fast.template
    width = float(np.ptp(project(template.model, template.params)[:, 0]))
    assert template.face_width_px == width
    assert vars(template)["_face_width_px"] == width  # kept on the template, not projected again


def test_the_description_reference_kept_is_the_one_made(head) -> None:
    """The description's picture is made once per size and kept: every call gets what
    making it gives, in its own copy."""
    from uma.mbc.scene_reference import _reference, description_reference

    for size in ((352, 288), (176, 144), (352, 288)):
        picture, params = description_reference(head.description, size)
        want, want_params = _reference(head.description, size)
        assert np.array_equal(picture, want) and np.array_equal(params, want_params)
        picture[:] = 0  # a caller drawing on its copy changes no later one
        params[:] = 0
    again, again_params = description_reference(head.description, (352, 288))
    assert again.any() and np.array_equal(again_params, _reference(head.description,
                                                                   (352, 288))[1])  # fmt: skip
