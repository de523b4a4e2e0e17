"""One refresh: `uma bench mbc` codes and takes refreshes with `uma.mbc`'s coder, the same
objects the simulation is to call (docs/refresh.md)."""

import numpy as np
import pytest


def test_the_bench_calls_the_mbc_refresh_coder_and_composition() -> None:
    import uma.bench.mbc_refresh as bench
    import uma.mbc.refresh_coder as coder

    assert bench.RefreshCoder is coder.RefreshCoder
    assert bench.take_refresh is coder.take_refresh
    assert bench.face_box_size is coder.face_box_size and bench.box_corner is coder.box_corner


def test_a_refresh_box_outside_the_picture_is_refused_and_the_reference_stays(head) -> None:
    from uma.mbc.errors import SceneError
    from uma.mbc.refresh_coder import take_refresh
    from uma.mbc.scene_render import SceneRenderer
    from uma.mbc.units import FaceUnits

    renderer = SceneRenderer(head.description, (352, 288))
    units = FaceUnits.of(head.model, head.description.params, light=True, body=True)
    values = np.concatenate([head.params_at(0), np.zeros(3), (1.0, 0.0)])
    before = renderer.reference.copy()
    patch = np.full((96 * 3 // 2, 64), 90, np.uint8)
    with pytest.raises(SceneError, match="outside the picture"):
        take_refresh(renderer, units, values, ((320, 10), patch))
    assert np.array_equal(renderer.reference, before)
    take_refresh(renderer, units, values, ((100, 60), patch))
    assert np.all(renderer.reference[70:145, 110:150] == 90)  # inside the feathered edge


def test_a_refresh_box_that_is_not_a_picture_is_refused_and_the_reference_stays(head) -> None:
    from uma.mbc.errors import SceneError
    from uma.mbc.refresh_coder import take_refresh
    from uma.mbc.scene_render import SceneRenderer
    from uma.mbc.units import FaceUnits

    renderer = SceneRenderer(head.description, (352, 288))
    units = FaceUnits.of(head.model, head.description.params, light=True, body=True)
    values = np.concatenate([head.params_at(0), np.zeros(3), (1.0, 0.0)])
    before = renderer.reference.copy()
    for bad in (np.full((95, 64), 90, np.uint8), np.full((96, 63), 90, np.uint8),
                np.full((96, 64), 90.0), np.zeros((0, 64), np.uint8)):  # fmt: skip
        with pytest.raises(SceneError, match="refresh box: expected"):
            take_refresh(renderer, units, values, ((100, 60), bad))
        assert np.array_equal(renderer.reference, before)


@pytest.mark.parametrize("codec", ["h264", "vp8", "av1"])
def test_the_refresh_codes_with_each_full_frame_codec_of_the_registry(codec) -> None:
    from uma.mbc.refresh_coder import MIN_CODED_PX, RefreshCoder
    from uma.mbc.refresh_judge import box_psnr_db
    from uma.video import default_ladder_path, load_ladder

    settings = load_ladder(default_ladder_path(codec)).encoder.kwargs()
    box = (96, 112)
    coder = RefreshCoder((176, 144), (48, 56), 5.0, 12.0, settings, box, codec)
    assert min(coder.coded) >= MIN_CODED_PX.get(codec, 2)
    y, x = np.mgrid[0:216, 0:176]
    frame = (x * 0.6 + y * 0.4 + 20).astype(np.uint8)  # a smooth ramp, easy to code
    try:
        bits, key, (corner, patch) = coder.code(frame, (40, 20))
        more, key_after, _ = coder.code(frame, (40, 20))
    finally:
        coder.close()
    assert key and not key_after and bits > 32 and more > 0
    assert corner == (40, 20) and patch.shape == (112 * 3 // 2, 96)
    truth = frame[20:132, 40:136]
    assert box_psnr_db(patch[:112], truth) > 25.0  # the box, decoded again


def test_an_unknown_refresh_codec_is_refused_by_name() -> None:
    from uma.mbc.errors import SceneError
    from uma.mbc.refresh_coder import refresh_codec_classes

    with pytest.raises(SceneError, match="h264, vp8, av1, got 'mbc'"):
        refresh_codec_classes("mbc")
