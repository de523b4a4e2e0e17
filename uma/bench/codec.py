"""`uma bench codec`: every codec's rate and quality per ladder rung, codec speed, metric costs.

Units: kbit/s, percent, dB, frames per second, milliseconds (wall clock; per-frame means for
the codecs, medians of repeats for the metrics). A rate is measured after the first second
(which carries the opening key frame). Clips are taken at 25 frames/s, the rate the ladders
divide.

`run_codec_bench` is libx264's rate accuracy on one clip, its speed and the metrics' cost (the
table this benchmark has always printed for H.264). `run_codecs_bench` codes clips (akiyo and
carphone from ../shared/data by default) at every rung of each codec's ladder: per rung the
target and measured rate, PSNR and SSIM of luma over the whole frame and over the face box the
simulation scores (`uma.face.region.FaceBoxes`), each decoded picture upscaled to the clip's
size as the receiver shows it and scored against the frame it codes, and the encode and decode
time per frame. `plot_rate_quality` draws those rate-quality curves.
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from uma.bench.codec_clip import Clip, open_clip
from uma.bench.timing import median_ms
from uma.codecs import full_frame_names, spec

__all__ = [
    "run_codec_bench",
    "format_table",
    "run_codecs_bench",
    "format_codecs_table",
    "plot_rate_quality",
    "codec_classes",
    "CODEC_NAMES",
    "CODEC_COLOURS",
]

# The full-frame codecs and their plot colours, as the codec registry names them.
CODEC_NAMES = full_frame_names()
CODEC_COLOURS = {name: spec(name).colour for name in CODEC_NAMES}
CLIP_FPS = 25.0
RUNG_KEYS = (
    "target_kbps",
    "kbps",
    "psnr_db",
    "ssim",
    "psnr_face_db",
    "ssim_face",
    "encode_ms",
    "decode_ms",
)


def run_codec_bench(*, video: Path | None, frames: int = 300) -> dict[str, Any]:
    """libx264's rate accuracy per rung, its speed and the metrics' cost on one clip (or the
    pattern when `video` is None), streaming the clip: at most `frames` of the frames it holds."""
    from uma.metrics.quality import psnr_db, ssim
    from uma.video import H264Decoder, H264Encoder, load_ladder, resize_yuv420

    clip = open_clip(video, frames, faces=False)
    rungs = []
    for rung in load_ladder().rungs:
        step = max(1, int(round(25.0 / rung.fps)))
        encoder = H264Encoder(rung.width, rung.height, rung.fps, rung.rate_kbps)
        bits = [
            encoder.encode(resize_yuv420(f, rung.width, rung.height)).size_bits
            for i, f in enumerate(clip.frames())
            if i % step == 0
        ]
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
    encoder, decoder = H264Encoder(clip.width, clip.height, 25.0, 768), H264Decoder()
    encode_s = decode_s = 0.0
    middle = None
    for index, frame in enumerate(clip.frames()):
        start = time.perf_counter()
        unit = encoder.encode(frame)
        coded = time.perf_counter()
        picture = decoder.decode(unit.data)
        decode_s += time.perf_counter() - coded
        encode_s += coded - start
        if index == clip.count // 2:
            middle = (frame[: clip.height], picture[: clip.height])
    ref, test = middle
    from skimage.metrics import structural_similarity

    return {
        "video": f"{clip.name} {clip.width}x{clip.height}",
        "frames": clip.count,
        "rungs": rungs,
        "encode_fps": round(clip.count / encode_s, 1),
        "decode_fps": round(clip.count / decode_s, 1),
        "ssim_ms_float32": round(median_ms(lambda: ssim(ref, test)), 3),
        "ssim_ms_uint8": round(
            median_ms(lambda: structural_similarity(ref, test, data_range=255)), 3
        ),
        "psnr_ms": round(median_ms(lambda: psnr_db(ref, test)), 3),
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


def codec_classes(codec: str) -> tuple[type, type]:
    """(encoder class, decoder class) of a full-frame codec, as the registry names them."""
    import uma.video

    entry = spec(codec)
    return getattr(uma.video, entry.video_encoder), getattr(uma.video, entry.video_decoder)


def _round(value: float, digits: int) -> float | None:
    return None if value != value else round(float(value), digits)  # NaN (no face) is null


def measure_rung(codec: str, rung, settings, frames: Iterable[np.ndarray], boxes) -> dict[str, Any]:
    """Code `frames` (a clip at 25 frames/s, read once, in order) at one rung and score the
    decoded pictures; `boxes[i]` is frame i's face box or None."""
    from uma.metrics.quality import psnr_db, region_scores, ssim
    from uma.video import resize_yuv420

    encoder_class, decoder_class = codec_classes(codec)
    encoder = encoder_class(rung.width, rung.height, rung.fps, rung.rate_kbps, **settings.kwargs())
    decoder = decoder_class()
    step = max(1, int(round(CLIP_FPS / rung.fps)))
    bits, encode_s, decode_s, scores = [], 0.0, 0.0, []
    for index, frame in enumerate(frames):
        if index % step:
            continue
        height, width = frame.shape[0] * 2 // 3, frame.shape[1]
        small = resize_yuv420(frame, rung.width, rung.height)
        start = time.perf_counter()
        unit = encoder.encode(small)
        middle = time.perf_counter()
        picture = decoder.decode(unit.data)
        decode_s += time.perf_counter() - middle
        encode_s += middle - start
        bits.append(unit.size_bits)
        shown = resize_yuv420(picture, width, height)[:height]
        reference = frame[:height]
        face = region_scores(reference, shown, boxes[index])
        scores.append((psnr_db(reference, shown), ssim(reference, shown), *face))
    skip = max(1, int(round(rung.fps)))
    kbps = sum(bits[skip:]) / ((len(bits) - skip) / rung.fps) / 1000.0
    table = np.array(scores, dtype=np.float64).reshape(-1, 4)
    # a column of NaN (no face box in any frame) stays NaN, without numpy's empty-slice warning
    means = [float(np.mean(c[~np.isnan(c)])) if (~np.isnan(c)).any() else np.nan for c in table.T]
    return {
        "target_kbps": rung.rate_kbps,
        "size": f"{rung.width}x{rung.height}@{rung.fps:.3g}",
        "kbps": round(kbps, 2),
        "error_pct": round(100.0 * (kbps / rung.rate_kbps - 1.0), 2),
        "psnr_db": _round(means[0], 2),
        "ssim": _round(means[1], 4),
        "psnr_face_db": _round(means[2], 2),
        "ssim_face": _round(means[3], 4),
        "encode_ms": round(1000.0 * encode_s / len(bits), 3),
        "decode_ms": round(1000.0 * decode_s / len(bits), 3),
    }


def run_codecs_bench(
    codecs: tuple[str, ...],
    videos: list[Path | None],
    *,
    frames: int = 300,
    progress=None,
    pattern_size: tuple[int, int] = (352, 288),
) -> dict[str, Any]:
    """`{"codecs": {codec: {"ladder", "clips": {clip: {"frames", "size", "rungs"}}}}}`.

    A `None` among `videos` is the built-in pattern at `pattern_size`.
    """
    from uma.video import default_ladder_path, load_ladder

    clips: list[Clip] = [open_clip(video, frames, pattern_size=pattern_size) for video in videos]
    result: dict[str, Any] = {"codecs": {}}
    for codec in codecs:
        path = default_ladder_path(codec)
        ladder = load_ladder(path)
        entry = {"ladder": f"codecs/{path.name}", "clips": {}}
        for clip in clips:
            rungs = []
            for rung in ladder.rungs:
                if progress is not None:
                    progress(f"{codec} {clip.name} {rung.label}")
                rungs.append(measure_rung(codec, rung, ladder.encoder, clip.frames(), clip.boxes))
            entry["clips"][clip.name] = {
                "frames": clip.count,
                "size": f"{clip.width}x{clip.height}",
                "rungs": rungs,
            }
        result["codecs"][codec] = entry
    return result


def format_codecs_table(result: dict[str, Any]) -> str:
    def num(value, fmt: str) -> str:
        return "-" if value is None else format(value, fmt)

    lines = []
    for codec, entry in result["codecs"].items():
        for clip, data in entry["clips"].items():
            lines += [
                f"{codec} ({entry['ladder']}) on {clip} {data['size']}, {data['frames']} frames",
                f"  {'rung':<16}{'target':>7}{'kbit/s':>9}{'err %':>7}{'PSNR':>7}{'SSIM':>8}"
                f"{'face PSNR':>10}{'face SSIM':>10}{'enc ms':>8}{'dec ms':>8}",
            ]
            for rung in data["rungs"]:
                lines.append(
                    f"  {rung['size']:<16}{rung['target_kbps']:>7g}{rung['kbps']:>9.1f}"
                    f"{rung['error_pct']:>7.1f}{num(rung['psnr_db'], '.2f'):>7}"
                    f"{num(rung['ssim'], '.4f'):>8}{num(rung['psnr_face_db'], '.2f'):>10}"
                    f"{num(rung['ssim_face'], '.4f'):>10}{rung['encode_ms']:>8.2f}"
                    f"{rung['decode_ms']:>8.2f}"
                )
            lines.append("")
    return "\n".join(lines)


def plot_rate_quality(result: dict[str, Any], path: Path) -> None:
    """Whole-frame and face-box PSNR against the measured rate, one row per clip, into `path`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from uma.atomic import atomic_write_bytes

    clips = list(next(iter(result["codecs"].values()))["clips"])
    figure, axes = plt.subplots(len(clips), 2, figsize=(9, 3.4 * len(clips)), squeeze=False)
    for row, clip in enumerate(clips):
        for col, (key, title) in enumerate(
            (("psnr_db", "whole frame"), ("psnr_face_db", "face box"))
        ):
            ax = axes[row][col]
            for codec, entry in result["codecs"].items():
                rungs = entry["clips"][clip]["rungs"]
                points = [(r["kbps"], r[key]) for r in rungs if r[key] is not None]
                if points:
                    x, y = zip(*points, strict=True)
                    ax.plot(x, y, marker="o", ms=3, color=CODEC_COLOURS.get(codec), label=codec)
            ax.set_xscale("log")
            ax.axvspan(16, 64, color="#eeeeee", lw=0, zorder=0)
            ax.set_title(f"{clip}: {title}", fontsize=10)
            ax.set_xlabel("measured rate (kbit/s)")
            ax.set_ylabel("luma PSNR (dB)")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
    figure.suptitle(
        "uma bench codec: luma PSNR per ladder rung, decoded and upscaled (grey: 16-64 kbit/s)",
        fontsize=10,
    )
    figure.tight_layout()
    import io

    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=110)
    plt.close(figure)
    atomic_write_bytes(path, buffer.getvalue())
