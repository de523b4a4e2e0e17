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
