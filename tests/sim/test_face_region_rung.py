"""The face-region H.264 rung: crop, code, composite, on real video frames."""

from pathlib import Path

import numpy as np
import pytest

from uma.config.scenario import FaceRegionConfig
from uma.engine.points import OperatingPoint
from uma.face.detect import Box
from uma.sim.face_region import (
    HEADER,
    FaceRegionDecoder,
    FaceRegionEncoder,
    crop_box,
    crop_yuv420,
    paste_yuv420,
)
from uma.sim.packets import EncodedUnit
from uma.video import load_ladder

AKIYO = Path(__file__).parents[2] / ".." / "shared" / "data" / "faces" / "video" / "akiyo.mp4"


def _psnr(a: np.ndarray, b: np.ndarray) -> float:
    mse = float(np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2))
    return 10 * np.log10(255.0**2 / max(mse, 1e-12))


def test_crop_box_is_even_inside_the_frame_and_shaped_like_the_coded_size():
    face = Box(140, 30, 61, 61)
    box = crop_box(face, face.centre, coded=(96, 64), source=(176, 144), margin=0.2)
    assert box.x % 2 == box.y % 2 == box.width % 2 == box.height % 2 == 0
    assert box.x + box.width <= 176 and box.y + box.height <= 144 and box.x >= 0
    assert abs(box.width / box.height - 96 / 64) < 0.05
    assert box.width >= 61 * 1.4 - 2  # the margin on both sides


def test_paste_of_a_crop_gives_the_picture_back():
    rng = np.random.default_rng(1)
    picture = rng.integers(0, 256, (144 * 3 // 2, 176), dtype=np.uint8)
    box = Box(40, 20, 64, 48)
    back = paste_yuv420(np.zeros_like(picture), crop_yuv420(picture, box), box)
    assert np.array_equal(crop_yuv420(back, box), crop_yuv420(picture, box))
    outside = back.copy()
    outside[20:68, 40:104] = 1
    assert np.count_nonzero(back[:144][outside[:144] != 1]) == 0


@pytest.mark.skipif(not AKIYO.exists(), reason="needs ../shared/data")
def test_round_trip_on_akiyo_composites_the_face_over_the_background():
    from uma.video import VideoFileSource

    source = VideoFileSource(str(AKIYO), loop=False)
    frames = source.frames()
    pictures = [next(frames) for _ in range(10)]
    size = (source.width, source.height)
    point = OperatingPoint("h264-face", 12.0, 5.0, 96, 96)
    config = FaceRegionConfig(enabled=True)
    encoder = FaceRegionEncoder(
        point,
        source_size=size,
        source_fps=25.0,
        settings=load_ladder().encoder,
        context={"face_region": config},
    )
    background = np.full_like(pictures[0], 90)
    decoder = FaceRegionDecoder(context={"source_size": size, "background": background})
    for frame in range(0, 10, 5):
        out = encoder.encode(pictures[frame], intra=frame == 0, frame=frame)
        assert not out.failure and out.data
        assert out.keyframe == (frame == 0)
        assert out.evaluations == (1 if frame == 0 else 0)  # the detector ran on the first
        x, y, w, h = HEADER.unpack_from(out.data)
        shown = decoder.decode(EncodedUnit(frame, frame, "h264-face", 0, 96, 96, True, out.data))
        composite = shown[frame]
        assert composite.shape == pictures[frame].shape
        inside = np.zeros(composite.shape, dtype=bool)
        inside[y : y + h, x : x + w] = True
        height = source.height
        luma_in = inside[:height]
        # Outside the box: the background, untouched (chroma too).
        assert np.all(composite[:height][~luma_in] == 90)
        assert np.count_nonzero(composite[height:] != 90) <= (w // 2) * (h // 2) * 2
        # Inside: close to the source (akiyo's face, 12 kbit/s at 96x96: about 24.5 dB on the IDR).
        src = pictures[frame][:height][y : y + h, x : x + w]
        assert _psnr(composite[:height][y : y + h, x : x + w], src) > 22.0
        # And it holds the face: the box covers the Haar box of the source.
        assert w >= 90 and h >= 90


def test_no_face_is_a_failure_not_a_picture():
    point = OperatingPoint("h264-face", 8.0, 5.0, 64, 64)
    encoder = FaceRegionEncoder(
        point,
        source_size=(176, 144),
        source_fps=25.0,
        settings=load_ladder().encoder,
        context={"face_region": FaceRegionConfig(enabled=True)},
    )
    flat = np.full((144 * 3 // 2, 176), 60, dtype=np.uint8)
    out = encoder.encode(flat, intra=True, frame=0)
    assert out.failure == "no face detected" and out.data == b""


def test_a_damaged_header_is_undecodable():
    decoder = FaceRegionDecoder(context={"source_size": (176, 144)})
    bad = HEADER.pack(170, 0, 64, 64) + b"\x00\x00\x00\x01"
    assert decoder.decode(EncodedUnit(0, 0, "h264-face", 0, 64, 64, True, bad)) == {}
