"""`uma bench quality`: the SSIM uma computes against scikit-image's, on real coded frames, and its cost.

Units: SSIM unitless, PSNR in dB, times in milliseconds (wall clock, medians of repeats, all
timed in the same process one after another). The pairs are a clip's source luma against what
the receiver would show: the frame coded by libx264 at a ladder rung (at the rung's size and
frame rate, after the first second so the IDR is left out), decoded and upscaled to the
source's size (bilinear), with the face box OpenCV's Haar detector finds in the source frame.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from uma.bench.timing import median_ms

__all__ = ["quality_pairs", "run_quality_bench", "format_table"]


def _clip_frames(path: Path, count: int) -> list[np.ndarray]:
    from uma.video import VideoFileSource

    source = VideoFileSource(path, loop=True, max_frames=count)
    return list(source.frames())


def quality_pairs(
    path: Path, per_rung: int, *, faces: bool = True
) -> list[tuple[str, np.ndarray, np.ndarray, Any]]:
    """(rung label, source luma, shown luma, face box or None): `per_rung` pairs at every rung.

    `faces=False` skips the face detector (every box None).
    """
    import cv2

    from uma.face.detect import detect_face
    from uma.video import H264Decoder, H264Encoder, load_ladder, resize_yuv420

    ladder = load_ladder()
    steps = [max(1, round(25.0 / rung.fps)) for rung in ladder.rungs]
    skips = [max(1, math.ceil(rung.fps)) for rung in ladder.rungs]
    needed = max(step * (skip + per_rung) for step, skip in zip(steps, skips, strict=True))
    frames = _clip_frames(path, needed)
    height, width = frames[0].shape[0] * 2 // 3, frames[0].shape[1]
    boxes: dict[int, Any] = {}
    pairs = []
    for rung, step, skip in zip(ladder.rungs, steps, skips, strict=True):
        encoder = H264Encoder(rung.width, rung.height, rung.fps, rung.rate_kbps)
        decoder = H264Decoder()
        chosen = list(range(0, step * (skip + per_rung), step))
        for order, index in enumerate(chosen):
            picture = decoder.decode(
                encoder.encode(resize_yuv420(frames[index], rung.width, rung.height)).data
            )
            if order < skip or picture is None:
                continue
            shown = picture[: rung.height]
            if shown.shape != (height, width):
                shown = cv2.resize(shown, (width, height), interpolation=cv2.INTER_LINEAR)
            reference = np.ascontiguousarray(frames[index][:height])
            if faces and index not in boxes:
                found = detect_face(reference)
                boxes[index] = found if found else None
            pairs.append(
                (f"{rung.rate_kbps:g}", reference, np.ascontiguousarray(shown), boxes.get(index))
            )
    return pairs


def _agreement(pairs) -> dict[str, Any]:
    from skimage.metrics import structural_similarity

    from uma.metrics.quality import frame_scores, psnr_db

    frame_diff, face_diff, float32_diff, psnr_diff, boxes = [], [], [], [], 0
    for _, ref, tst, box in pairs:
        psnr, similarity, face_psnr, face_ssim = frame_scores(ref, tst, box)
        exact = structural_similarity(ref, tst, data_range=255)  # float64 inside
        frame_diff.append(abs(similarity - exact))
        old = structural_similarity(
            ref.astype(np.float32), tst.astype(np.float32), data_range=255.0
        )
        float32_diff.append(abs(similarity - old))
        psnr_diff.append(abs(psnr - psnr_db(ref, tst)))
        if box is not None and min(box.width, box.height) >= 7:
            y0, x0 = max(0, box.y), max(0, box.x)
            crop = (slice(y0, box.y + box.height), slice(x0, box.x + box.width))
            face_exact = structural_similarity(ref[crop], tst[crop], data_range=255)
            face_diff.append(abs(face_ssim - face_exact))
            boxes += 1
    return {
        "pairs": len(pairs),
        "pairs_with_face": boxes,
        "ssim_max_abs_diff": float(max(frame_diff)),
        "ssim_face_max_abs_diff": float(max(face_diff)) if face_diff else None,
        "ssim_max_abs_diff_vs_float32": float(max(float32_diff)),
        "psnr_max_abs_diff_db": float(max(psnr_diff)),
    }


def _timings(ref: np.ndarray, tst: np.ndarray, box, repeats: int) -> dict[str, float]:
    from skimage.metrics import structural_similarity

    from uma.metrics.quality import frame_scores, ssim

    ref32, tst32 = ref.astype(np.float32), tst.astype(np.float32)
    crop = (slice(box.y, box.y + box.height), slice(box.x, box.x + box.width))

    def old_frame_scores() -> None:
        # the previous scoring: scikit-image on float32, whole plane, then the face crop again
        structural_similarity(ref32, tst32, data_range=255.0)
        structural_similarity(ref32[crop], tst32[crop], data_range=255.0)

    return {
        "ssim_ms": round(median_ms(lambda: ssim(ref, tst), repeats), 3),
        "skimage_float32_ms": round(
            median_ms(lambda: structural_similarity(ref32, tst32, data_range=255.0), repeats), 3
        ),
        "skimage_uint8_ms": round(
            median_ms(lambda: structural_similarity(ref, tst, data_range=255), repeats), 3
        ),
        "frame_scores_ms": round(median_ms(lambda: frame_scores(ref, tst, box), repeats), 3),
        "old_frame_and_face_ms": round(median_ms(old_frame_scores, repeats), 3),
    }


def run_quality_bench(*, clips: dict[str, Path], pairs: int = 200, repeats: int = 100) -> dict:
    """Agreement with scikit-image over about `pairs` real pairs, and CIF timings side by side.

    Timings run twice: first with the process's malloc as it comes, then after
    `keep_freed_memory()` (which changes scikit-image's cost most: it allocates per call).
    """
    from uma.face.detect import Box
    from uma.metrics.quality import keep_freed_memory
    from uma.video import load_ladder

    per_rung = max(1, math.ceil(pairs / (len(clips) * len(load_ladder().rungs))))
    all_pairs = []
    for path in clips.values():
        all_pairs += quality_pairs(path, per_rung)
    result: dict[str, Any] = {"clips": {name: str(path) for name, path in clips.items()}}
    result.update(_agreement(all_pairs))
    cif = [p for p in all_pairs if p[1].shape == (288, 352)] or all_pairs
    label, ref, tst, box = cif[len(cif) // 2]
    box = box or Box(ref.shape[1] // 4, ref.shape[0] // 4, ref.shape[1] // 2, ref.shape[0] // 2)
    timing: dict[str, Any] = {
        "plane": f"{ref.shape[1]}x{ref.shape[0]}",
        "rung_kbps": label,
        "box": [box.x, box.y, box.width, box.height],
    }
    timing["default_malloc"] = _timings(ref, tst, box, repeats)
    timing["keep_freed_memory"] = _timings(ref, tst, box, repeats) if keep_freed_memory() else None
    for row in (timing["default_malloc"], timing["keep_freed_memory"]):
        if row:
            row["speedup_vs_float32"] = round(row["skimage_float32_ms"] / row["ssim_ms"], 2)
            row["speedup_frame_and_face"] = round(
                row["old_frame_and_face_ms"] / row["frame_scores_ms"], 2
            )
    result["timing"] = timing
    return result


def format_table(result: dict[str, Any]) -> str:
    timing = result["timing"]
    face = result["ssim_face_max_abs_diff"]
    lines = [
        f"uma bench quality: {result['pairs']} pairs ({result['pairs_with_face']} with a face box)"
        f" from {', '.join(result['clips'])}",
        "",
        f"  SSIM, max |uma - scikit-image (float64)|  frame {result['ssim_max_abs_diff']:.2e}"
        f", face box {'n/a' if face is None else format(face, '.2e')}",
        f"  SSIM, max |uma - scikit-image (float32)|  {result['ssim_max_abs_diff_vs_float32']:.2e}",
        f"  PSNR, max |frame_scores - psnr_db|       {result['psnr_max_abs_diff_db']:.2e} dB",
        "",
        f"  ms per {timing['plane']} luma plane (rung {timing['rung_kbps']} kbit/s), medians",
        f"  {'malloc':<20}{'uma':>8}{'sk f32':>9}{'sk u8':>8}{'x':>7}"
        f"{'frame+face':>13}{'old':>8}{'x':>7}",
    ]
    for name in ("default_malloc", "keep_freed_memory"):
        row = timing[name]
        if row is None:
            continue
        lines.append(
            f"  {name:<20}{row['ssim_ms']:>8.3f}{row['skimage_float32_ms']:>9.3f}"
            f"{row['skimage_uint8_ms']:>8.3f}{row['speedup_vs_float32']:>7.1f}"
            f"{row['frame_scores_ms']:>13.3f}{row['old_frame_and_face_ms']:>8.3f}"
            f"{row['speedup_frame_and_face']:>7.1f}"
        )
    return "\n".join(lines)
