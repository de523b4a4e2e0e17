import cv2
import numpy as np
import pytest
import skimage.data

from uma.face import (
    make_params,
    project,
    rasterize,
    render,
    sample_bilinear,
    visible_triangles,
    warp_points,
)
from uma.metrics.quality import psnr_db


@pytest.fixture(scope="module")
def template(face_model):
    gray = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2GRAY)
    model = face_model
    params = make_params(model, tx_px=224, ty_px=118, scale_px=68)
    return gray, model, params


def test_rendering_template_at_its_own_pose_reproduces_it(template):
    gray, model, params = template
    points = project(model, params)
    result = render(gray, points, points, model.triangles, gray.shape)
    assert result.mask.sum() > 5000
    assert psnr_db(gray[result.mask], result.image[result.mask]) > 35


def test_forward_and_inverse_mappings_agree(template):
    gray, model, params = template
    source = project(model, params)
    moved = params.copy()
    moved[[0, 1, 2, 4, 5]] += [9.0, -6.0, 6.0, 0.12, 0.05]
    target = project(model, moved)
    visible = visible_triangles(model, moved)
    image = render(gray, source, target, model.triangles, gray.shape, visible=visible).image
    # Inverse: sample the rendered image where each template pixel went.
    raster = rasterize(source, model.triangles, gray.shape, triangle_mask=visible)
    samples = sample_bilinear(image, warp_points(raster, target))
    original = gray[raster.ys, raster.xs].astype(np.float32)
    # Ignore pixels on triangle borders, where the two bilinear resamplings differ most.
    interior = raster.bary.min(axis=1) > 0.05
    assert psnr_db(original[interior], samples[interior]) > 30


def test_batched_warp_matches_single(template):
    gray, model, params = template
    raster = rasterize(project(model, params), model.triangles, gray.shape)
    rng = np.random.default_rng(2)
    batch = np.repeat(params[None], 12, axis=0)
    batch[:, :6] += rng.normal(0, [3.0, 3.0, 2.0, 0.05, 0.1, 0.05], (12, 6))
    points = project(model, batch).reshape(3, 4, model.n_vertices, 2)
    together = warp_points(raster, points)
    assert together.shape == (3, 4, raster.size, 2) and together.dtype == np.float32
    for i, j in ((0, 0), (2, 3)):
        alone = warp_points(raster, points[i, j])
        assert np.allclose(together[i, j], alone, atol=1e-3)
        # Barycentric interpolation by hand.
        corners = points[i, j][raster.corners]
        assert np.allclose(alone, np.einsum("kj,kjd->kd", raster.bary, corners), atol=1e-3)
    values = sample_bilinear(gray, together)
    assert values.shape == (3, 4, raster.size) and values.dtype == np.float32
    # The strided layout warp_points returns and a plain contiguous copy sample alike.
    assert np.array_equal(values, sample_bilinear(gray, np.ascontiguousarray(together)))
    assert np.allclose(values[1, 2], sample_bilinear(gray, together[1, 2]))


def test_sample_bilinear_interpolates_and_fills():
    ramp = np.tile(np.arange(8, dtype=np.float32) * 10, (6, 1))  # value = 10 x
    xy = np.array([[[2.5, 1.0], [0.25, 3.0], [-5.0, 2.0], [100.0, 2.0]]], dtype=np.float32)
    assert np.allclose(sample_bilinear(ramp, xy)[0], [25.0, 2.5, 0.0, 70.0], atol=0.2)
    assert np.allclose(sample_bilinear(ramp, xy, fill=-1.0)[0, 2:], [-1.0, -1.0])
    colour = np.dstack([ramp, 2 * ramp, 3 * ramp])
    assert np.allclose(sample_bilinear(colour, xy[0, :1])[0], [25.0, 50.0, 75.0], atol=0.5)
    # Longer than one cv2 map row.
    many = np.tile(np.array([[2.5, 1.0]], np.float32), (40_000, 1))
    assert np.allclose(sample_bilinear(ramp, many), 25.0, atol=0.2)


def test_rasterize_covers_without_cracks(template):
    gray, model, params = template
    points = project(model, params)
    raster = rasterize(points, model.triangles, gray.shape)
    mask = np.zeros(gray.shape, dtype=np.uint8)
    mask[raster.ys, raster.xs] = 1
    hull = np.zeros_like(mask)
    cv2.fillConvexPoly(
        hull, np.round(cv2.convexHull(points.astype(np.float32))).astype(np.int32), 1
    )
    inner = cv2.erode(hull, np.ones((5, 5), np.uint8))
    assert mask[inner > 0].all()
    assert np.allclose(raster.bary.sum(axis=1), 1.0, atol=1e-5)
