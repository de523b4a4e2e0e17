import math
import platform
import sys

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from skimage.metrics import structural_similarity

from uma.metrics import PSNR_CAP_DB, SSIM_DB_CAP, keep_freed_memory, psnr_db, ssim, ssim_db


def test_identical_planes_hit_the_caps_never_inf():
    plane = np.random.default_rng(0).integers(0, 256, (64, 64), dtype=np.uint8)
    assert psnr_db(plane, plane) == PSNR_CAP_DB == 100.0
    assert ssim(plane, plane) == pytest.approx(1.0)
    assert ssim_db(ssim(plane, plane)) == SSIM_DB_CAP


def test_psnr_of_a_constant_error():
    a = np.full((32, 32), 100, dtype=np.uint8)
    assert psnr_db(a, a + np.uint8(5)) == pytest.approx(10 * np.log10(255**2 / 25))
    assert psnr_db(a + np.uint8(5), a) == psnr_db(a, a + np.uint8(5))  # no uint8 wrap-around


@pytest.mark.parametrize("sigma", [1.0, 4.0, 12.0])
def test_psnr_of_gaussian_noise_of_known_variance(sigma):
    rng = np.random.default_rng(int(sigma))
    plane = np.full((288, 352), 128.0)
    noisy = np.clip(np.round(plane + rng.normal(0, sigma, plane.shape)), 0, 255)
    # rounding to integers adds the variance of a uniform quantiser, 1/12
    expected = 10 * np.log10(255**2 / (sigma**2 + 1 / 12))
    assert psnr_db(plane.astype(np.uint8), noisy.astype(np.uint8)) == pytest.approx(
        expected, abs=0.05
    )


def test_ssim_of_flat_planes_follows_the_luminance_term():
    # flat planes have no variance, so SSIM reduces to (2ab + C1) / (a^2 + b^2 + C1)
    c1 = (0.01 * 255) ** 2
    for a, b in ((100, 110), (50, 200)):
        got = ssim(np.full((32, 32), a, np.uint8), np.full((32, 32), b, np.uint8))
        assert got == pytest.approx((2 * a * b + c1) / (a * a + b * b + c1), rel=1e-5)


def test_ssim_matches_scikit_image_in_float64():
    rng = np.random.default_rng(1)
    ref = (rng.random((144, 176)) * 200).astype(np.uint8)
    test = np.clip(ref + rng.normal(0, 8, ref.shape), 0, 255).astype(np.uint8)
    exact = structural_similarity(ref, test, data_range=255)  # uint8 in, float64 inside
    assert ssim(ref, test) == pytest.approx(exact, abs=1e-5)


def test_ssim_falls_with_noise():
    rng = np.random.default_rng(1)
    plane = (rng.random((72, 88)) * 200).astype(np.uint8)
    light = np.clip(plane + rng.normal(0, 3, plane.shape), 0, 255).astype(np.uint8)
    heavy = np.clip(plane + rng.normal(0, 30, plane.shape), 0, 255).astype(np.uint8)
    assert 0 < ssim(plane, heavy) < ssim(plane, light) < 1


def test_downscaled_ssim_is_ssim_of_block_means():
    rng = np.random.default_rng(2)
    # a smooth picture (as natural ones are) of odd size: the last row and column are dropped
    field = cv2.GaussianBlur(rng.random((145, 177)), (0, 0), 3)
    ref = np.interp(field, (field.min(), field.max()), (20, 235)).astype(np.uint8)
    test = np.clip(ref + rng.normal(0, 10, ref.shape), 0, 255).astype(np.uint8)

    def block_mean(plane):
        p = plane[:144, :176].astype(np.float64)
        return p.reshape(72, 2, 88, 2).mean(axis=(1, 3))

    expected = structural_similarity(block_mean(ref), block_mean(test), data_range=255.0)
    assert ssim(ref, test, scale=2) == pytest.approx(expected, abs=1e-5)
    # averaging hides white noise more than smooth detail: downscaled SSIM reads higher
    assert ssim(ref, test, scale=2) > ssim(ref, test)


def test_bad_arguments():
    with pytest.raises(ValueError, match="different shapes"):
        psnr_db(np.zeros((4, 4)), np.zeros((4, 5)))
    with pytest.raises(ValueError, match="different shapes"):
        ssim(np.zeros((16, 16)), np.zeros((16, 15)))
    with pytest.raises(ValueError, match="scale"):
        ssim(np.zeros((16, 16)), np.zeros((16, 16)), scale=0)
    with pytest.raises(ValueError, match="at least 7x7"):
        ssim(np.zeros((16, 16)), np.zeros((16, 16)), scale=4)


def test_ssim_db():
    assert ssim_db(0.9) == pytest.approx(10.0)
    assert ssim_db(0.99) == pytest.approx(20.0)
    assert ssim_db(0.0) == 0.0
    assert ssim_db(1.0) == SSIM_DB_CAP and ssim_db(1.0 - 1e-12) == SSIM_DB_CAP
    assert ssim_db(-0.5) < 0
    assert math.isnan(ssim_db(float("nan")))


@settings(max_examples=50, deadline=None)
@given(st.floats(-1.0, 1.0))
def test_ssim_db_is_finite_and_increasing(value):
    db = ssim_db(value)
    assert math.isfinite(db) and db <= SSIM_DB_CAP
    assert ssim_db(min(1.0, value + 0.01)) >= db


def test_keep_freed_memory_changes_speed_not_values():
    rng = np.random.default_rng(3)
    ref = (rng.random((288, 352)) * 255).astype(np.uint8)
    test = np.clip(ref + rng.normal(0, 6, ref.shape), 0, 255).astype(np.uint8)
    before = ssim(ref, test)
    applied = keep_freed_memory()
    assert isinstance(applied, bool)
    if sys.platform.startswith("linux") and "glibc" in " ".join(platform.libc_ver()):
        assert applied
    assert ssim(ref, test) == before


def test_face_region_scores_see_only_the_face_box():
    import math

    from uma.face import Box
    from uma.metrics.quality import PSNR_CAP_DB, psnr_db, region_scores, ssim

    rng = np.random.default_rng(0)
    reference = rng.integers(0, 256, (72, 88), dtype=np.uint8)
    box = Box(20, 10, 30, 40)
    assert region_scores(reference, reference.copy(), box) == (psnr_db(reference, reference), 1.0)
    assert region_scores(reference, reference, box)[0] == PSNR_CAP_DB
    outside = reference.copy()
    outside[:, 60:] = 0  # changed, but right of the box
    assert region_scores(reference, outside, box) == (PSNR_CAP_DB, 1.0)
    assert psnr_db(reference, outside) < PSNR_CAP_DB
    inside = reference.copy()
    inside[20:30, 25:35] = 255 - inside[20:30, 25:35]
    face_psnr, face_ssim = region_scores(reference, inside, box)
    assert face_psnr < 30 and face_ssim < 0.95
    assert face_ssim == ssim(reference[10:50, 20:50], inside[10:50, 20:50])
    nan_psnr, nan_ssim = region_scores(reference, inside, None)
    assert math.isnan(nan_psnr) and math.isnan(nan_ssim)
    off = region_scores(reference, inside, box, with_psnr=False, with_ssim=False)
    assert all(math.isnan(v) for v in off)


def _random_pair(rng, shape, noise):
    ref = rng.integers(0, 256, shape, dtype=np.uint8)
    test = np.clip(ref + rng.normal(0, noise, shape), 0, 255).astype(np.uint8)
    return ref, test


@pytest.mark.parametrize("shape", [(7, 7), (9, 31), (144, 176), (288, 352)])
def test_ssim_matches_scikit_image_on_every_dtype(shape):
    rng = np.random.default_rng(shape[0])
    ref, test = _random_pair(rng, shape, 20)
    exact = structural_similarity(ref, test, data_range=255)
    assert ssim(ref, test) == pytest.approx(exact, abs=1e-6)
    # other dtypes take the float64 filters
    assert ssim(ref.astype(np.float32), test.astype(np.float32)) == pytest.approx(exact, abs=1e-9)
    assert ssim(ref.astype(np.int16), test) == pytest.approx(exact, abs=1e-9)


def test_frame_scores_give_the_values_of_the_separate_functions():
    from uma.face import Box
    from uma.metrics.quality import frame_scores, region_scores

    rng = np.random.default_rng(5)
    ref, test = _random_pair(rng, (72, 88), 15)
    boxes = [Box(20, 10, 30, 40), Box(-5, -5, 20, 30), Box(70, 60, 40, 40), Box(3, 3, 6, 20)]
    for box in boxes:
        psnr, similarity, face_psnr, face_ssim = frame_scores(ref, test, box)
        assert psnr == psnr_db(ref, test) and similarity == ssim(ref, test)
        # the box's SSIM is the frame map over the box less its border: the crop's SSIM exactly
        assert (face_psnr, face_ssim) == pytest.approx(region_scores(ref, test, box), nan_ok=True)
    assert math.isnan(frame_scores(ref, test, boxes[3])[3])  # 6 px wide: no face SSIM
    assert all(math.isnan(v) for v in frame_scores(ref, test, None)[2:])
    assert all(math.isnan(v) for v in frame_scores(ref, test, Box(200, 200, 5, 5))[2:])
    off = frame_scores(ref, test, boxes[0], with_psnr=False, with_ssim=False)
    assert all(math.isnan(v) for v in off)


def test_face_ssim_equals_scikit_image_on_the_crop():
    from uma.face import Box
    from uma.metrics.quality import frame_scores

    rng = np.random.default_rng(6)
    ref, test = _random_pair(rng, (144, 176), 25)
    for box in (Box(40, 30, 60, 70), Box(0, 0, 50, 144), Box(150, 100, 26, 44)):
        crop = (slice(box.y, box.y + box.height), slice(box.x, box.x + box.width))
        exact = structural_similarity(ref[crop], test[crop], data_range=255)
        assert frame_scores(ref, test, box)[3] == pytest.approx(exact, abs=1e-6)


def test_scores_are_independent_of_threads_and_reused_buffers():
    from concurrent.futures import ThreadPoolExecutor

    from uma.face import Box
    from uma.metrics.quality import frame_scores

    rng = np.random.default_rng(7)
    pairs = [_random_pair(rng, (144, 176), noise) for noise in (2, 10, 40, 80)] * 3
    box = Box(30, 20, 80, 90)
    serial = [frame_scores(r, t, box) for r, t in pairs]
    with ThreadPoolExecutor(3) as pool:
        threaded = list(pool.map(lambda p: frame_scores(p[0], p[1], box), pairs))
    assert threaded == serial
    assert len(set(serial)) == 4


def test_ssim_agrees_with_scikit_image_on_real_coded_frames(shared_data):
    from uma.bench.quality import quality_pairs

    clip = shared_data / "faces" / "video" / "carphone_qcif.mp4"
    pairs = quality_pairs(clip, per_rung=1, faces=False)
    assert len(pairs) == 9  # one at each rung of the ladder
    for _, ref, test, _box in pairs:
        assert ssim(ref, test) == pytest.approx(
            structural_similarity(ref, test, data_range=255), abs=1e-6
        )


@pytest.mark.slow
def test_ssim_within_1e_4_of_scikit_image_on_200_real_pairs(shared_data):
    from uma.bench.quality import _agreement, quality_pairs

    folder = shared_data / "faces" / "video"
    pairs = quality_pairs(folder / "akiyo.mp4", 12) + quality_pairs(
        folder / "carphone_qcif.mp4", 12
    )
    agreement = _agreement(pairs)
    assert agreement["pairs"] >= 200 and agreement["pairs_with_face"] >= 150
    assert agreement["ssim_max_abs_diff"] < 1e-4
    assert agreement["ssim_face_max_abs_diff"] < 1e-4
    assert agreement["psnr_max_abs_diff_db"] == 0.0


def test_buffers_of_old_shapes_are_dropped():
    import uma.metrics.quality as quality

    rng = np.random.default_rng(8)
    ref, test = _random_pair(rng, (64, 64), 10)
    expected = [
        structural_similarity(ref[:h, :h], test[:h, :h], data_range=255) for h in range(8, 40)
    ]
    got = [ssim(ref[:h, :h], test[:h, :h]) for h in range(8, 40)]  # 32 shapes
    assert got == pytest.approx(expected, abs=1e-6)
    assert len(quality._buffers.shapes) == quality._SHAPES_KEPT
    assert ssim(ref, test) == pytest.approx(
        structural_similarity(ref, test, data_range=255), abs=1e-6
    )
