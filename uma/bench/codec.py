"""`uma bench codec`: libx264's rate accuracy per rung, codec speed, and the cost of the metrics.

Units: kbit/s, percent, frames per second, milliseconds (wall clock, medians of repeats).
The rate is measured after the first second (which carries the IDR) on a real clip: akiyo (CIF
talking head) from ../shared/data when present, else the built-in pattern.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["run_codec_bench", "format_table"]


def _frames(video: Path | None, count: int) -> tuple[list[np.ndarray], str]:
    from uma.video import PatternSource, VideoFileSource

    if video is not None and video.is_file():
        source = VideoFileSource(video, loop=True, max_frames=count)
        name = video.name
    else:
        source = PatternSource(352, 288, seed=0)
        name = "pattern"
    iterator = iter(source.frames())
    return [next(iterator) for _ in range(count)], name


def _median_ms(fn, repeats: int = 30) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times) * 1000.0)


def run_codec_bench(*, video: Path | None, frames: int = 300) -> dict[str, Any]:
    from uma.metrics.quality import psnr_db, ssim
    from uma.video import H264Decoder, H264Encoder, load_ladder, resize_yuv420

    clip, name = _frames(video, frames)
    height = clip[0].shape[0] * 2 // 3
    width = clip[0].shape[1]
    rungs = []
    for rung in load_ladder().rungs:
        step = max(1, int(round(25.0 / rung.fps)))
        chosen = [resize_yuv420(f, rung.width, rung.height) for f in clip[::step]]
        encoder = H264Encoder(rung.width, rung.height, rung.fps, rung.rate_kbps)
        bits = [encoder.encode(f).size_bits for f in chosen]
        skip = max(1, int(rung.fps))
        measured = sum(bits[skip:]) / ((len(bits) - skip) / rung.fps) / 1000.0
        rungs.append(
            {
                "rate_kbps": rung.rate_kbps,
                "size": f"{rung.width}x{rung.height}@{rung.fps:g}",
                "measured_kbps": round(measured, 2),
                "error_pct": round(100.0 * (measured / rung.rate_kbps - 1.0), 2),
            }
        )
    encoder, decoder = H264Encoder(width, height, 25.0, 768), H264Decoder()
    start = time.perf_counter()
    packets = [encoder.encode(f) for f in clip]
    encode_s = time.perf_counter() - start
    start = time.perf_counter()
    pictures = [decoder.decode(p.data) for p in packets]
    decode_s = time.perf_counter() - start
    ref, test = clip[len(clip) // 2][:height], pictures[len(clip) // 2][:height]
    from skimage.metrics import structural_similarity

    return {
        "video": f"{name} {width}x{height}",
        "frames": len(clip),
        "rungs": rungs,
        "encode_fps": round(len(clip) / encode_s, 1),
        "decode_fps": round(len(clip) / decode_s, 1),
        "ssim_ms_float32": round(_median_ms(lambda: ssim(ref, test)), 3),
        "ssim_ms_uint8": round(
            _median_ms(lambda: structural_similarity(ref, test, data_range=255)), 3
        ),
        "psnr_ms": round(_median_ms(lambda: psnr_db(ref, test)), 3),
    }


def format_table(result: dict[str, Any]) -> str:
    lines = [
        f"uma bench codec: {result['video']}, {result['frames']} frames",
        "",
        f"  {'rung':<22}{'target kbit/s':>14}{'measured':>10}{'error %':>9}",
    ]
    for rung in result["rungs"]:
        lines.append(
            f"  {rung['size']:<22}{rung['rate_kbps']:>14g}{rung['measured_kbps']:>10.1f}{rung['error_pct']:>9.1f}"
        )
    lines += [
        "",
        f"  libx264 encode {result['encode_fps']} frames/s, FFmpeg decode {result['decode_fps']} frames/s (ultrafast, zerolatency, 768 kbit/s)",
        f"  SSIM per luma plane {result['ssim_ms_float32']} ms on float32, {result['ssim_ms_uint8']} ms on uint8; PSNR {result['psnr_ms']} ms",
    ]
    return "\n".join(lines)
