"""`uma bench mbc`: the model-based codec end to end on a clip, scored against the true frames.

Units: kbit/s at 25 frames/s (a clip at another rate is scaled); PSNR in dB and SSIM on luma;
milliseconds per frame, wall clock and this process's CPU time (medians; measured here
only, never inside the codec).

Per clip: the tracker (`uma.mbc.encoder`) analyses every frame (the first, and any it loses,
by the hybrid initialisation), the parameter encoder codes them into packets, the decoder
decodes those packets, and the renderer draws the personal model at the decoded parameters
over the first frame (the last full picture the receiver had). Four displays are scored
against the true frames, over the whole frame and over the face region (the pixels the model
covers at the tracked parameters, or at the ground truth on the talking head): the rendering
at the tracker's unquantised parameters, at the decoded (quantised) ones, the frozen display
(the first frame held: what H.264 shows in an outage), and H.264 at the ladder's lowest rung on
the same frames (real libx264, decoded, upscaled, each picture held until the next). Frame 0,
the one the receiver holds in full, is not scored.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["ClipSpec", "run_mbc_bench", "format_table", "default_clips", "DISPLAYS"]

DISPLAYS = ("unquantised", "quantised", "frozen", "h264_lowest")
SCALED_FPS = 25.0


@dataclass(frozen=True, eq=False)
class ClipSpec:
    """A clip to code: YUV 4:2:0 frames, its rate, the description, ground truth if any."""

    name: str
    frames: list[np.ndarray]
    fps: float
    description: Any  # ContentDescription
    truth: Callable[[int], np.ndarray] | None = None
    where: str = ""


def talking_head_clip(frames: int, *, seed: int = 0) -> ClipSpec:
    import cv2

    from uma.face.talking_head import TalkingHeadSource

    source = TalkingHeadSource(352, 288, seed=seed)
    noise = np.random.default_rng(seed)
    yuv = [
        cv2.cvtColor(source.render_bgr(i, rng=noise), cv2.COLOR_BGR2YUV_I420) for i in range(frames)
    ]
    return ClipSpec(
        "talking-head", yuv, source.fps, source.description, source.params_at, "talking head"
    )


def file_clip(video: Path, description, frames: int, *, name: str | None = None) -> ClipSpec:
    from uma.video import VideoFileSource

    source = VideoFileSource(video, max_frames=frames)
    return ClipSpec(
        name or video.stem, list(source.frames()), source.fps, description, None, str(video)
    )


def default_clips(frames: int, *, seed: int = 0) -> list[ClipSpec]:
    """The talking head, then akiyo and carphone with the shipped clicked points (skipped
    when ../shared/data is absent)."""
    from uma.face.clip import describe_clip, load_points
    from uma.paths import codecs_dir

    clips = [talking_head_clip(frames, seed=seed)]
    for name in ("akiyo", "carphone"):
        points_file = codecs_dir() / "face" / f"{name}.yaml"
        points = load_points(points_file)
        video = Path(points.video) if points.video is not None else None
        if video is None or not video.is_file():
            continue
        clips.append(file_clip(video, describe_clip(points), frames, name=name))
    return clips


def _luma(frame: np.ndarray) -> np.ndarray:
    return frame[: frame.shape[0] * 2 // 3]


def _h264_lowest(frames: list[np.ndarray], fps: float) -> tuple[list[np.ndarray], float, str]:
    """The lowest rung's display at the source size, and its measured rate (kbit/s)."""
    from uma.video import H264Decoder, H264Encoder, load_ladder, resize_yuv420

    ladder = load_ladder()
    rung = ladder.rungs[0]
    height, width = _luma(frames[0]).shape
    step = max(1, int(round(fps / rung.fps)))
    encoder = H264Encoder(
        rung.width, rung.height, rung.fps, rung.rate_kbps, **ladder.encoder.kwargs()
    )
    decoder = H264Decoder()
    shown, bits, last = [], 0, None
    for index, frame in enumerate(frames):
        if index % step == 0:
            unit = encoder.encode(resize_yuv420(frame, rung.width, rung.height))
            bits += unit.size_bits
            picture = decoder.decode(unit.data)
            if picture is not None:
                last = _luma(resize_yuv420(picture, width, height))
        shown.append(last if last is not None else np.full((height, width), 128, np.uint8))
    coded = -(-len(frames) // step)
    return shown, bits / (coded / rung.fps) / 1000.0, rung.label


def _scores(reference: np.ndarray, test: np.ndarray, mask: np.ndarray) -> tuple[float, ...]:
    """(PSNR frame, SSIM frame, PSNR face, SSIM face): one SSIM map serves both."""
    from skimage.metrics import structural_similarity

    from uma.metrics.quality import PSNR_CAP_DB

    ref = reference.astype(np.float32)
    tst = test.astype(np.float32)
    diff = (ref - tst) ** 2

    def psnr(mse: float) -> float:
        return PSNR_CAP_DB if mse <= 255.0**2 * 1e-10 else float(10 * np.log10(255.0**2 / mse))

    similarity, full = structural_similarity(ref, tst, data_range=255.0, full=True)
    face = mask if mask.any() else np.ones_like(mask)
    return (
        psnr(float(diff.mean())),
        float(similarity),
        psnr(float(diff[face].mean())),
        float(full[face].mean()),
    )


def _median(values: list[float]) -> float | None:
    return round(float(np.median(values)), 3) if values else None


def run_clip(clip: ClipSpec, *, seed: int = 0, stream_config=None, tracker_config=None) -> dict:
    """Code one clip and score it; see the module docstring."""
    from uma.errors import VideoError
    from uma.fit.mde import mde_px
    from uma.mbc.decoder import FaceRenderer, ParameterDecoder
    from uma.mbc.encoder import FaceTracker, TrackerConfig
    from uma.mbc.packets import IP_UDP_RTP_BYTES
    from uma.mbc.stream import ParameterEncoder, StreamConfig
    from uma.mbc.units import FaceUnits

    stream_config = stream_config or StreamConfig()
    description = clip.description
    lumas = [_luma(f) for f in clip.frames]
    height, width = lumas[0].shape
    # One untimed initialisation first: numba loads its compiled kernels on first use.
    FaceTracker(description, rng=seed).track(lumas[0])
    tracker = FaceTracker(description, config=tracker_config or TrackerConfig(), rng=seed)
    units = FaceUnits.of(description.model, description.params)
    encoder = ParameterEncoder(units, stream_config)
    track_ms, init_ms, results, packets = [], [], [], []
    track_cpu, init_cpu = [], []
    for index, picture in enumerate(lumas):
        begin, cpu = time.perf_counter(), time.process_time()
        result = tracker.track(picture, frame=index)
        elapsed = (time.perf_counter() - begin) * 1000.0
        (init_ms if result.reinitialised else track_ms).append(elapsed)
        (init_cpu if result.reinitialised else track_cpu).append(
            (time.process_time() - cpu) * 1000.0
        )
        results.append(result)
        packets += encoder.push(index, result.params if result else None)
    packets += encoder.flush()
    if not any(results):
        reasons = {r.reason.split(": ", 1)[-1] for r in results}
        raise VideoError(
            f"{clip.where or clip.name}: no face tracked in any of {len(results)} frames "
            f"({'; '.join(sorted(reasons)[:2])})"
        )
    # The receiver: decode every packet in order, render each frame at the newest parameters.
    decoder = ParameterDecoder(units, stream_config)
    renderer = FaceRenderer(description, (width, height), background=lumas[0])
    decoded: dict[int, np.ndarray] = {}
    decode_ms: dict[int, tuple[float, float]] = {}
    for packet in packets:
        data = packet.to_bytes()
        begin, cpu = time.perf_counter(), time.process_time()
        out = decoder.decode(data)
        count = max(len(out.frames), 1)
        share = (
            (time.perf_counter() - begin) * 1000.0 / count,
            (time.process_time() - cpu) * 1000.0 / count,
        )
        for frame, params in out.frames:
            decoded[frame] = params
            decode_ms[frame] = share
    render_ms, render_cpu = [], []
    sums = {d: np.zeros(4) for d in DISPLAYS}
    h264, h264_kbps, rung = _h264_lowest(clip.frames, clip.fps)
    tracked = quantised = None
    tracked_mask = np.zeros((height, width), bool)
    shown_tracked = shown_quantised = lumas[0]
    mde = []
    scored = 0
    for index in range(len(lumas)):
        result = results[index]
        if result:
            tracked = result.params
            shown_tracked, tracked_mask = renderer.render(tracked)
        if index in decoded:
            begin, cpu = time.perf_counter(), time.process_time()
            quantised = decoded[index]
            shown_quantised, _ = renderer.render(quantised)
            render_ms.append(decode_ms[index][0] + (time.perf_counter() - begin) * 1000.0)
            render_cpu.append(decode_ms[index][1] + (time.process_time() - cpu) * 1000.0)
        if clip.truth is not None and result:
            mde.append(mde_px(description.model, result.params, clip.truth(index)))
        if index == 0:
            continue
        mask = tracked_mask
        if clip.truth is not None:
            _, mask = renderer.render(clip.truth(index))
        truth = lumas[index]
        for name, shown in zip(
            DISPLAYS, (shown_tracked, shown_quantised, lumas[0], h264[index]), strict=True
        ):
            sums[name] += _scores(truth, shown, mask)
        scored += 1
    means = {d: sums[d] / max(scored, 1) for d in DISPLAYS}
    payload_bytes = sum(p.size_bytes for p in packets)
    wire_bytes = payload_bytes + IP_UDP_RTP_BYTES * len(packets)
    seconds = len(lumas) / SCALED_FPS  # the same frames at 25 frames/s
    reinits = [r for r in results[1:] if r.reinitialised]
    return {
        "frames": len(lumas),
        "size": f"{width}x{height}",
        "fps": round(clip.fps, 3),
        "rate_kbps": round(payload_bytes * 8 / seconds / 1000.0, 3),
        "wire_kbps": round(wire_bytes * 8 / seconds / 1000.0, 3),
        "packets": len(packets),
        "frames_per_packet": stream_config.frames_per_packet,
        "payload_bytes_per_frame": round(payload_bytes / len(lumas), 2),
        "psnr_loss_db": round(float(means["unquantised"][2] - means["quantised"][2]), 3),
        "reinits": len(reinits),
        "lost_tracks": sum(r.reason.startswith("track lost") for r in reinits),
        "failures": sum(not r for r in results),
        "reinit_reasons": sorted({r.reason.split(" (")[0] for r in reinits}),
        "evaluations_median": _median(
            [r.evaluations for r in results[1:] if r and not r.reinitialised]
        ),
        "track_ms_median": _median(track_ms),
        "init_ms_median": _median(init_ms),
        "render_ms_median": _median(render_ms),
        # CPU time of this process (time.process_time): on a shared machine, wall clock also
        # counts the time other processes held the cores.
        "track_cpu_ms_median": _median(track_cpu),
        "init_cpu_ms_median": _median(init_cpu),
        "render_cpu_ms_median": _median(render_cpu),
        "mde_median_px": round(float(np.median(mde)), 4) if mde else None,
        "mde_p95_px": round(float(np.percentile(mde, 95)), 4) if mde else None,
        "h264_lowest": {"rung": rung, "rate_kbps": round(h264_kbps * SCALED_FPS / clip.fps, 2)},
        "face": {
            d: {"psnr_db": round(float(means[d][2]), 3), "ssim": round(float(means[d][3]), 4)}
            for d in DISPLAYS
        },
        "frame": {
            d: {"psnr_db": round(float(means[d][0]), 3), "ssim": round(float(means[d][1]), 4)}
            for d in DISPLAYS
        },
    }


def run_mbc_bench(clips: list[ClipSpec], *, seed: int = 0, progress=None) -> dict[str, Any]:
    from uma.metrics.quality import keep_freed_memory

    keep_freed_memory()
    out: dict[str, Any] = {"seed": seed, "clips": {}}
    for clip in clips:
        if progress is not None:
            progress(clip.name)
        out["clips"][clip.name] = run_clip(clip, seed=seed)
    return out


def format_table(result: dict[str, Any]) -> str:
    lines = ["uma bench mbc: model-based codec, payload and wire rates at 25 frames/s", ""]
    head = (
        f"  {'clip':<14}{'frames':>7}{'size':>9}{'kbit/s':>8}{'wire':>7}{'loss dB':>8}"
        f"{'reinits':>8}{'track ms':>9}{'init ms':>8}{'render ms':>10}{'MDE px':>8}{'p95':>7}"
        f"   cpu ms: {'track':>6}{'init':>6}{'render':>7}"
    )
    lines.append(head)

    def num(value, fmt):
        return "-" if value is None else format(value, fmt)

    for name, c in result["clips"].items():
        lines.append(
            f"  {name:<14}{c['frames']:>7}{c['size']:>9}{c['rate_kbps']:>8.2f}{c['wire_kbps']:>7.2f}"
            f"{c['psnr_loss_db']:>8.2f}{c['reinits']:>8}{num(c['track_ms_median'], '.1f'):>9}"
            f"{num(c['init_ms_median'], '.0f'):>8}{num(c['render_ms_median'], '.2f'):>10}"
            f"{num(c['mde_median_px'], '.3f'):>8}{num(c['mde_p95_px'], '.3f'):>7}"
            f"           {num(c['track_cpu_ms_median'], '.1f'):>6}{num(c['init_cpu_ms_median'], '.0f'):>6}"
            f"{num(c['render_cpu_ms_median'], '.2f'):>7}"
        )
    lines += [
        "",
        f"  {'clip':<14}{'display':<13}{'face PSNR dB':>13}{'SSIM':>8}{'frame PSNR dB':>15}{'SSIM':>8}",
    ]
    for name, c in result["clips"].items():
        for d in DISPLAYS:
            label = d if d != "h264_lowest" else f"h264 {c['h264_lowest']['rung'].split()[0]}"
            lines.append(
                f"  {name:<14}{label:<13}{c['face'][d]['psnr_db']:>13.2f}{c['face'][d]['ssim']:>8.4f}"
                f"{c['frame'][d]['psnr_db']:>15.2f}{c['frame'][d]['ssim']:>8.4f}"
            )
    return "\n".join(lines)
