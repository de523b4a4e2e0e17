"""The description's luma is the luma the codecs see (I420, BT.601 limited range)."""

import numpy as np
import pytest

from uma.face.colour import bgr_to_luma, bgr_to_ycbcr, ycbcr_to_bgr


def test_luma_matches_opencv_i420() -> None:
    import cv2

    rng = np.random.default_rng(0)
    image = rng.integers(0, 256, (32, 48, 3), dtype=np.uint8)
    i420 = cv2.cvtColor(image, cv2.COLOR_BGR2YUV_I420)
    assert np.abs(bgr_to_luma(image).astype(int) - i420[:32]).max() <= 1


def test_colour_round_trip() -> None:
    rng = np.random.default_rng(1)
    image = rng.integers(30, 220, (16, 16, 3), dtype=np.uint8)
    back = ycbcr_to_bgr(bgr_to_ycbcr(image))
    assert np.abs(back.astype(int) - image).max() <= 1


def test_akiyo_description_luma_is_the_frames(shared_data) -> None:
    from uma.face.clip import describe_clip, shipped_points
    from uma.face.points import load_points
    from uma.face.render import rasterize
    from uma.video import VideoFileSource

    points = load_points(shipped_points("akiyo"))
    if points.video is None or not points.video.is_file():
        pytest.skip("akiyo not in the shared data")
    description = describe_clip(points)
    frame = next(iter(VideoFileSource(points.video, max_frames=1).frames()))
    height = frame.shape[0] * 2 // 3
    luma = frame[:height].astype(np.float64)
    x0, y0 = (int(v) for v in description.origin_px)
    gray = description.gray.astype(np.float64)
    h, w = gray.shape
    raster = rasterize(description.projected(), description.model.triangles, (h, w))
    face = luma[y0 : y0 + h, x0 : x0 + w][raster.ys, raster.xs]
    mine = gray[raster.ys, raster.xs]
    rms = float(np.sqrt(np.mean((face - mine) ** 2)))
    assert rms <= 1.5, f"description luma differs from the frame's by {rms:.2f} levels rms"
