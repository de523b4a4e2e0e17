"""Measure the face-region H.264 rung on real clips at the codec level: choose settings, quote quality.

Units: rates in kbit/s, sizes in pixels, PSNR in dB.

`uma bench face-rung --grid CLIP` codes the first `--frames` frames of a clip
at each candidate face-region setting (rate, coded size, frame rate, margin) and scores what
the receiver would show: each decoded composite held until the next, over the picture shown
before the switch (the lowest full-frame rung's first picture), scored on luma over the source's
face box as a run scores it (OpenCV's Haar box, `uma.face.region.FaceBoxes`), against the
lowest full-frame rung shown the same way. `--quote CLIP` does the same for the configured
default rungs only. Whole runs and the detector's cost are in `uma.bench.face_rung_run`.
Settings are chosen on one clip and quoted on another (docs/face-region.md).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["CLIPS", "code_clip", "lowest_rung_scores", "grid", "quote", "face_config", "load_clip"]

CLIPS = {
    "akiyo": "faces/video/akiyo.mp4",
    "carphone": "faces/video/carphone_qcif.mp4",
}


def load_clip(name: str, frames: int):
    from uma.paths import shared_data_dir
    from uma.video import VideoFileSource

    path = Path(name)
    if not path.is_file():
        path = shared_data_dir() / CLIPS[name]
    source = VideoFileSource(path, max_frames=frames)
    return source, list(source.frames()), str(path)


def _boxes(source, pictures) -> list:
    from uma.face.region import FaceBoxes

    boxes = FaceBoxes(source)
    list(boxes.wrap(iter(pictures)))
    return boxes.boxes


def _scheduled(frames: int, fps: float, source_fps: float) -> list[int]:
    """Source frames a point of `fps` keeps (the engine's frame clock)."""
    ratio = min(1.0, fps / source_fps)
    return [i for i in range(frames) if int((i + 1) * ratio + 1e-9) > int(i * ratio + 1e-9)]


def _scores(pictures, shown, boxes) -> dict[str, float]:
    from uma.metrics.quality import region_scores

    height = pictures[0].shape[0] * 2 // 3
    psnr, ssim = [], []
    for source, picture, box in zip(pictures, shown, boxes, strict=True):
        if box is None:
            continue
        p, s = region_scores(source[:height], picture[:height], box)
        psnr.append(p)
        ssim.append(s)
    return {
        "psnr_face_db": round(float(np.mean(psnr)), 2),
        "ssim_face": round(float(np.mean(ssim)), 4),
    }


def _lowest_rung(pictures, fps: float):
    """The lowest full-frame rung's display (decoded, upscaled, held) and its rate."""
    from uma.engine.points import full_frame_points
    from uma.sim.codecs import FullFramePointEncoder, FullFrameUnitDecoder
    from uma.sim.packets import EncodedUnit
    from uma.video import load_ladder, resize_yuv420

    ladder = load_ladder()  # H.264's: the face rung sits below the H.264 ladder it compares with
    point = full_frame_points(ladder, codec=ladder.codec, transcode_ms=0.0)[0]
    height = pictures[0].shape[0] * 2 // 3
    width = pictures[0].shape[1]
    encoder = FullFramePointEncoder(
        point, source_size=(width, height), source_fps=fps, settings=ladder.encoder
    )
    decoder = FullFrameUnitDecoder(codec=ladder.codec)
    keep = set(_scheduled(len(pictures), point.fps, fps))
    shown, bits, last = [], 0, None
    for index, picture in enumerate(pictures):
        if index in keep:
            out = encoder.encode(picture, intra=not bits)
            bits += 8 * len(out.data)
            unit = EncodedUnit(index, index, ladder.codec, 0, 0, 0, out.keyframe, out.data)
            decoded = decoder.decode(unit).get(index)
            if decoded is not None:
                last = resize_yuv420(decoded, width, height)
        shown.append(last)
    # Before its first picture the display shows it too (as the face rung's background).
    first = next(picture for picture in shown if picture is not None)
    shown = [first if picture is None else picture for picture in shown]
    return shown, bits / (len(pictures) / fps) / 1000.0, point.label


def lowest_rung_scores(pictures, fps: float, boxes) -> dict[str, Any]:
    shown, kbps, label = _lowest_rung(pictures, fps)
    return {"label": label, "kbps": round(kbps, 2)} | _scores(pictures, shown, boxes)


def code_clip(
    pictures,
    fps: float,
    boxes,
    background,
    *,
    rate_kbps,
    width,
    height,
    rung_fps,
    margin,
    detect_every_frames=25,
    smoothing=0.5,
) -> dict[str, Any]:
    """Code `pictures` at one face-region setting and score the display."""
    from uma.codecs import Role, names
    from uma.config.scenario import FaceRegionConfig
    from uma.engine.points import OperatingPoint
    from uma.sim.context import CodecContext
    from uma.sim.face_region import FaceRegionDecoder, FaceRegionEncoder
    from uma.sim.packets import EncodedUnit
    from uma.video import load_ladder

    config = FaceRegionConfig(
        enabled=True, margin=margin, detect_every_frames=detect_every_frames, smoothing=smoothing
    )
    height_px = pictures[0].shape[0] * 2 // 3
    size = (pictures[0].shape[1], height_px)
    region_name = names(Role.REGION)[0]
    point = OperatingPoint(region_name, rate_kbps, rung_fps, width, height)
    encoder = FaceRegionEncoder(
        point,
        source_size=size,
        source_fps=fps,
        settings=load_ladder().encoder,
        context=CodecContext(face_region=config),
    )
    decoder = FaceRegionDecoder(context=CodecContext(source_size=size, background=background))
    keep = set(_scheduled(len(pictures), rung_fps, fps))
    shown, bits, last, failures = [], 0, background, 0
    for index, picture in enumerate(pictures):
        if index in keep:
            out = encoder.encode(picture, intra=not bits, frame=index)
            if out.failure:
                failures += 1
            else:
                bits += 8 * len(out.data)
                unit = EncodedUnit(
                    index, index, region_name, 0, width, height, out.keyframe, out.data
                )
                last = decoder.decode(unit).get(index, last)
        shown.append(last)
    return {
        "rate_kbps": rate_kbps,
        "size": f"{width}x{height}",
        "fps": rung_fps,
        "margin": margin,
        "kbps": round(bits / (len(pictures) / fps) / 1000.0, 2),
        "failures": failures,
    } | _scores(pictures, shown, boxes)


def _background(pictures, fps):
    """The lowest full-frame rung's first picture: what the display showed before the switch."""
    shown, _, _ = _lowest_rung(pictures[:25], fps)
    return shown[0]


GRID_SIZES = ((32, 32), (48, 48), (64, 64), (80, 80), (96, 96), (112, 112), (128, 128))
GRID_FPS = (5.0, 8.333333, 12.5)
GRID_MARGINS = (0.1, 0.2, 0.3)


def grid(name: str, frames: int, rates=(8.0, 12.0)) -> dict[str, Any]:
    source, pictures, path = load_clip(name, frames)
    fps = float(source.fps)
    boxes = _boxes(source, pictures)
    background = _background(pictures, fps)
    rows = []
    for rate in rates:
        for width, height in GRID_SIZES:
            if width > source.width or height > source.height:
                continue
            for rung_fps in GRID_FPS:
                for margin in GRID_MARGINS:
                    rows.append(
                        code_clip(
                            pictures,
                            fps,
                            boxes,
                            background,
                            rate_kbps=rate,
                            width=width,
                            height=height,
                            rung_fps=rung_fps,
                            margin=margin,
                        )
                    )
    return {
        "clip": path,
        "frames": len(pictures),
        "h264_lowest": lowest_rung_scores(pictures, fps, boxes),
        "grid": rows,
    }


def face_config(rungs: list[str] | None):
    """The default `FaceRegionConfig`, enabled, its rungs replaced by `RATE:WxH@FPS` ones."""
    from uma.config.scenario import FaceRegionConfig, FaceRungConfig

    if not rungs:
        return FaceRegionConfig(enabled=True)
    from pydantic import ValidationError

    from uma.errors import ConfigError

    parsed = []
    for text in rungs:
        try:
            rate, rest = text.split(":")
            size, fps = rest.split("@")
            width, height = size.split("x")
            parsed.append(
                FaceRungConfig(
                    rate_kbps=float(rate), width=int(width), height=int(height), fps=float(fps)
                )
            )
        except (ValueError, ValidationError):
            raise ConfigError(
                f"--rung: expected RATE:WxH@FPS (e.g. 8:48x48@5), got {text!r}"
            ) from None
    return FaceRegionConfig(enabled=True, rungs=tuple(parsed))


def quote(name: str, frames: int, rungs: list[str] | None = None) -> dict[str, Any]:
    source, pictures, path = load_clip(name, frames)
    fps = float(source.fps)
    boxes = _boxes(source, pictures)
    background = _background(pictures, fps)
    config = face_config(rungs)
    rows = [
        code_clip(
            pictures,
            fps,
            boxes,
            background,
            rate_kbps=rung.rate_kbps,
            width=rung.width,
            height=rung.height,
            rung_fps=rung.fps,
            margin=config.margin,
            detect_every_frames=config.detect_every_frames,
            smoothing=config.smoothing,
        )
        for rung in config.rungs
        if rung.width <= source.width and rung.height <= source.height
    ]
    return {
        "clip": path,
        "frames": len(pictures),
        "h264_lowest": lowest_rung_scores(pictures, fps, boxes),
        "h264_face": rows,
    }
