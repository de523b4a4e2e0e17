"""`uma bench mbc`: the model-based codec end to end on a clip, scored against the true frames.

Units: kbit/s at 25 frames/s (a clip at another rate is scaled; H.264's displays at the clip's
own rate); PSNR in dB on luma and on chroma, SSIM on luma (`uma.bench.mbc_scores`);
milliseconds per frame, wall clock and this process's CPU time (medians; measured here only,
never inside the codec).

Per clip: the tracker (`uma.mbc.encoder`) analyses every frame (the first, and any it loses,
by the hybrid initialisation); the encoder measures each frame's light against what the
receiver will render (`uma.mbc.light`), and the parameter encoder codes pose, action units
and light into packets; the decoder decodes them, and the receiver's `SceneRenderer` warps the
whole reference (frame 0, the last full picture the receiver had, at the pose tracked on it)
to each decoded pose, in colour. Displays: the rendering at the tracker's unquantised
parameters, at the decoded ones, the same stream from the other reference (the description's
picture) and with the face from the description (the simulation's choice), the frozen
display (frame 0 held: what H.264 shows in an outage), and H.264 at the
ladder's lowest and second rungs (real libx264, decoded, upscaled, each picture held until
the next). Where the tracker has no face the last good picture stays. Each is scored over the
face box of `uma.face.region` (as the simulation scores), the whole frame and the model's own
pixels. Frame 0, the one the receiver holds in full, is not scored.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from uma.bench.mbc_clips import ClipSpec, default_clips, file_clip, talking_head_clip
from uma.bench.mbc_refresh import DEFAULT_REFRESH
from uma.bench.mbc_table import format_table, summarise

__all__ = [
    "ClipSpec",
    "run_mbc_bench",
    "format_table",
    "default_clips",
    "file_clip",
    "talking_head_clip",
    "DISPLAYS",
]

BASE_DISPLAYS = (
    "unquantised",
    "quantised",
    "frozen",
    "h264_lowest",
    "h264_second",
    "h264_lowest_delayed",
    "h264_second_delayed",
    "av1_lowest",
    "av1_second",
    "av1_lowest_delayed",
    "av1_second_delayed",
    "vp8_lowest",
    "vp8_second",
    "vp8_lowest_delayed",
    "vp8_second_delayed",
    "other_reference",
    "description_face",
)
DISPLAYS = BASE_DISPLAYS + tuple(DEFAULT_REFRESH)
REGIONS = ("face", "frame", "model")
SCALED_FPS = 25.0
FULL_FRAME_CODECS = ("h264", "av1", "vp8")  # names in `uma.codecs`
RING_CHOICE_FRAMES = 25  # the first second: the sender's look at the call before it settles
MODEL_OWN = "model's own rendering"
LARGEST_MOTION = -1  # `run_clip(keep_frame=)`: keep the frame of the largest head motion


def _luma(frame: np.ndarray) -> np.ndarray:
    return frame[: frame.shape[0] * 2 // 3]


def _median(values: list[float]) -> float | None:
    return round(float(np.median(values)), 3) if values else None


def _track(clip: ClipSpec, lumas: list[np.ndarray], seed: int, tracker_config):
    """Every frame's `TrackResult` or `TrackFailure`, and the wall and CPU ms per kind."""
    from uma.mbc.encoder import FaceTracker, TrackerConfig

    # One untimed initialisation first: numba loads its compiled kernels on first use.
    FaceTracker(clip.description, rng=seed).track(lumas[0])
    tracker = FaceTracker(clip.description, config=tracker_config or TrackerConfig(), rng=seed)
    times: dict[str, list[float]] = {"track": [], "init": [], "track_cpu": [], "init_cpu": []}
    results = []
    for index, picture in enumerate(lumas):
        begin, cpu = time.perf_counter(), time.process_time()
        result = tracker.track(picture, frame=index)
        kind = "init" if result.reinitialised else "track"
        times[kind].append((time.perf_counter() - begin) * 1000.0)
        times[kind + "_cpu"].append((time.process_time() - cpu) * 1000.0)
        results.append(result)
    return results, times


def _largest_motion(results) -> int:
    """The frame whose tracked head lies farthest from frame 0's (the first tracked one's)."""
    tracked = [(i, r.params) for i, r in enumerate(results) if r]
    if len(tracked) < 2:
        return len(results) - 1
    first = tracked[0][1]
    return max(tracked[1:], key=lambda item: float(np.hypot(*(item[1][:2] - first[:2]))))[0]


def _choose_ring(clip: ClipSpec, results) -> float:
    """The head ring the sender picks on the call's first `RING_CHOICE_FRAMES` frames (from
    frame 0 at its tracked pose, as the receiver renders), used for the whole clip."""
    from uma.mbc.light import choose_head_ring
    from uma.mbc.scene_render import HEAD_RING_OUTLINES

    tracked = [i for i in range(1, min(RING_CHOICE_FRAMES + 1, len(results))) if results[i]]
    if not results[0] or not tracked:
        return HEAD_RING_OUTLINES
    pictures = [clip.frames[i] for i in tracked]
    poses = [results[i].params for i in tracked]
    return choose_head_ring(clip.description, clip.frames[0], results[0].params, pictures, poses)


def _renderer(clip: ClipSpec, reference: str, first, size, head_ring: float | None = None):
    """The receiver's renderer: from the last full picture (frame 0, at the pose tracked on
    it) or from the description's own picture."""
    from uma.mbc.scene_render import SceneRenderer

    renderer = SceneRenderer(clip.description, size, head_ring_outlines=head_ring)
    if reference == "picture" and first:
        renderer.set_reference(clip.frames[0], first.params)
    return renderer


def run_clip(
    clip: ClipSpec,
    *,
    seed: int = 0,
    stream_config=None,
    tracker_config=None,
    reference: str = "picture",
    keep_frame: int | None = None,
    kept: dict | None = None,
    refresh: dict | None = None,
) -> dict:
    """Code one clip and score it; see the module docstring. `refresh` names the
    `mbc_refresh_*` displays (`uma.bench.mbc_refresh.RefreshSpec` by name; default
    `DEFAULT_REFRESH`)."""
    from uma.bench.mbc_refresh import refresh_display
    from uma.bench.mbc_scores import RegionSums, codec_display, face_box
    from uma.errors import VideoError
    from uma.face.geometry import project
    from uma.fit.mde import mde_px
    from uma.mbc.body import BodyTracker
    from uma.mbc.decoder import ParameterDecoder
    from uma.mbc.light import measure_light
    from uma.mbc.packets import IP_UDP_RTP_BYTES
    from uma.mbc.stream import ParameterEncoder, StreamConfig
    from uma.mbc.units import FaceUnits

    stream_config = stream_config or StreamConfig()
    description = clip.description
    lumas = [_luma(f) for f in clip.frames]
    height, width = lumas[0].shape
    results, times = _track(clip, lumas, seed, tracker_config)
    if keep_frame == LARGEST_MOTION:
        keep_frame = _largest_motion(results)
    if not any(results):
        reasons = {r.reason.split(": ", 1)[-1] for r in results}
        raise VideoError(
            f"{clip.where or clip.name}: no face tracked in any of {len(results)} frames "
            f"({'; '.join(sorted(reasons)[:2])})"
        )
    # The encoder's mirror of the receiver: its light is measured against what it will show.
    units = FaceUnits.of(description.model, description.params, light=True, body=True)
    encoder = ParameterEncoder(units, stream_config)
    ring = _choose_ring(clip, results)
    mirror = _renderer(clip, reference, results[0], (width, height), ring)
    other = _renderer(clip, "description" if reference == "picture" else "picture",
                      results[0], (width, height), ring)  # fmt: skip
    # The simulation's choice: the scene from the picture, the face from the description.
    mixed = _renderer(clip, "picture", results[0], (width, height), ring)
    mixed.set_face_source(True)
    lights, other_lights, mixed_lights, light_ms, packets = {}, {}, {}, [], []
    bodies, body_ms, body_tracker = {}, [], BodyTracker()
    for index, result in enumerate(results):
        if result:
            begin = time.perf_counter()
            lights[index] = measure_light(mirror, lumas[index], result.params)
            light_ms.append((time.perf_counter() - begin) * 1000.0)
            begin = time.perf_counter()
            body_tracker.measure(mirror, lumas[index])  # a failure sends the last good one
            bodies[index] = body_tracker.last
            body_ms.append((time.perf_counter() - begin) * 1000.0)
            other_lights[index] = measure_light(other, lumas[index], result.params)
            mixed_lights[index] = measure_light(mixed, lumas[index], result.params)
        values = None
        if result:
            values = np.concatenate([result.params, bodies[index], lights[index]])
        packets += encoder.push(index, values)
    packets += encoder.flush()
    # The receiver: decode every packet in order, render each frame at the newest parameters.
    decoder = ParameterDecoder(units, stream_config)
    receiver = _renderer(clip, reference, results[0], (width, height), ring)
    decoded: dict[int, np.ndarray] = {}
    decode_ms: dict[int, float] = {}
    for packet in packets:
        data = packet.to_bytes()
        begin = time.perf_counter()
        out = decoder.decode(data)
        share = (time.perf_counter() - begin) * 1000.0 / max(len(out.frames), 1)
        for frame, values in out.frames:
            decoded[frame], decode_ms[frame] = values, share
    # Every full-frame codec at the ladder's two lowest rungs, shown at once and on arrival.
    h264 = {
        f"{codec}_{rung_name}{'_delayed' if late else ''}": codec_display(
            clip.frames, clip.fps, rung, codec, delayed=late
        )
        for codec in FULL_FRAME_CODECS
        for rung_name, rung in (("lowest", 0), ("second", 1))
        for late in (False, True)
    }
    # The refresh spends the rung's rate minus the plain stream's, both at the clip's own rate.
    refresh = DEFAULT_REFRESH if refresh is None else refresh
    mbc_clip_kbps = sum(p.size_bytes for p in packets) * 8 / (len(lumas) / clip.fps) / 1000.0
    refreshed = {
        name: refresh_display(
            clip, results, units, stream_config, mbc_clip_kbps, spec, head_ring=ring
        )
        for name, spec in refresh.items()
    }
    displays = BASE_DISPLAYS + tuple(refresh)
    sums = {d: RegionSums() for d in displays}
    rendered = ("unquantised", "quantised", "other_reference", "description_face")
    shown = {d: clip.frames[0] for d in rendered}
    model_mask = np.zeros((height, width), bool)
    render_ms, mde, box = [], [], None
    for index in range(len(lumas)):
        result = results[index]
        if result:  # no face: the last good picture stays (no mask in the wrong place)
            shown["unquantised"], model_mask = receiver.render(
                result.params, lights[index], bodies[index]
            )
        if index in decoded:
            begin = time.perf_counter()
            params, light = units.split(decoded[index])
            body = units.body_of(decoded[index])
            shown["quantised"], _ = receiver.render(params, light, body)
            render_ms.append(decode_ms[index] + (time.perf_counter() - begin) * 1000.0)
            shown["other_reference"], _ = other.render(params, other_lights[index])
            shown["description_face"], _ = mixed.render(params, mixed_lights[index], body)
        truth_points = None
        if clip.truth is not None:
            truth = clip.truth(index)
            truth_points = project(description.model, truth)
            if result:
                mde.append(mde_px(description.model, result.params, truth))
            _, model_mask = receiver.render(truth)
        box = face_box(lumas[index], truth_points, box)
        if index == 0:
            continue
        pictures = dict(shown, frozen=clip.frames[0],
                        **{name: h264[name][0][index] for name in h264},
                        **{name: refreshed[name][0][index] for name in refreshed})  # fmt: skip
        for name in displays:
            sums[name].add(clip.frames[index], pictures[name], box, model_mask)
        if kept is not None and index == keep_frame:
            kept.update(pictures, source=clip.frames[index])
    payload_bytes = sum(p.size_bytes for p in packets)
    wire_bytes = payload_bytes + IP_UDP_RTP_BYTES * len(packets)
    seconds = len(lumas) / SCALED_FPS  # the same frames at 25 frames/s
    rate_kbps = payload_bytes * 8 / seconds / 1000.0
    rates = {"unquantised": None, "quantised": rate_kbps, "frozen": 0.0,
             "other_reference": rate_kbps, "description_face": rate_kbps}  # fmt: skip
    rates.update({name: h264[name][1] for name in h264})
    rates.update({name: refreshed[name][1] for name in refreshed})
    scored = {name: sums[name].means(rates[name]) for name in displays}
    reinits = [r for r in results[1:] if r.reinitialised]
    stages = {
        "track": _median(times["track"]),
        "light": _median(light_ms),
        "body": _median(body_ms),
        "decode_render": _median(render_ms),
        "refresh": refreshed["mbc_refresh_lowest"][2]["ms_per_frame"]
        if "mbc_refresh_lowest" in refreshed
        else None,
    }
    face_psnr = {d: scored[d]["face"]["psnr_db"] for d in ("unquantised", "quantised")}
    return {
        "frames": len(lumas),
        "kept_frame": keep_frame,
        "size": f"{width}x{height}",
        "fps": round(clip.fps, 3),
        "reference": reference,
        "head_ring_outlines": ring,
        "rate_kbps": round(rate_kbps, 3),
        "wire_kbps": round(wire_bytes * 8 / seconds / 1000.0, 3),
        "packets": len(packets),
        "frames_per_packet": stream_config.frames_per_packet,
        "payload_bytes_per_frame": round(payload_bytes / len(lumas), 2),
        "psnr_loss_db": round(face_psnr["unquantised"] - face_psnr["quantised"], 3),
        "reinits": len(reinits),
        "lost_tracks": sum(r.reason.startswith("track lost") for r in reinits),
        "failures": sum(not r for r in results),
        "reinit_reasons": sorted({r.reason.split(" (")[0] for r in reinits}),
        "evaluations_median": _median(
            [r.evaluations for r in results[1:] if r and not r.reinitialised]
        ),
        "track_ms_median": _median(times["track"]),
        "init_ms_median": _median(times["init"]),
        "light_ms_median": _median(light_ms),
        "body_ms_median": _median(body_ms),
        # The model path per frame, stage by stage (medians; the refresh's per frame of the
        # clip at the lowest rung): the engine's tracking, light (its measure against the
        # mirror, the mirror's only rendering) and body motion, the receiver's decoding and
        # rendering, the refresh's coding and composition.
        "stages_ms": stages,
        "model_path_ms": round(sum(v for v in stages.values() if v is not None), 3),
        "render_ms_median": _median(render_ms),
        # CPU time of this process (time.process_time): on a shared machine, wall clock also
        # counts the time other processes held the cores.
        "track_cpu_ms_median": _median(times["track_cpu"]),
        "init_cpu_ms_median": _median(times["init_cpu"]),
        "mde_median_px": round(float(np.median(mde)), 4) if mde else None,
        "mde_p95_px": round(float(np.percentile(mde, 95)), 4) if mde else None,
        **{
            f"{c}_{r}": {"rung": h264[f"{c}_{r}"][2]}
            for c in FULL_FRAME_CODECS
            for r in ("lowest", "second")
        },  # fmt: skip
        "refresh": {name: refreshed[name][2] for name in refreshed},
        **{region: {d: scored[d][region] for d in displays} for region in REGIONS},
    }


def run_mbc_bench(
    clips: list[ClipSpec], *, seed: int = 0, progress=None, picture: Path | None = None
) -> dict[str, Any]:
    """Every clip's scores; with `picture`, the side-by-side PNG of each clip at its largest
    head motion (the tracked head farthest from frame 0's)."""
    from uma.metrics.quality import keep_freed_memory

    keep_freed_memory()
    out: dict[str, Any] = {"seed": seed, "clips": {}}
    rows = []
    for clip in clips:
        if progress is not None:
            progress(clip.name)
        kept: dict = {}
        result = run_clip(clip, seed=seed, keep_frame=LARGEST_MOTION, kept=kept)
        # The talking head is the face model's own rendering: it flatters any model codec and
        # never enters the real clips' summary.
        result["kind"] = MODEL_OWN if clip.truth is not None else "real clip"
        out["clips"][clip.name] = result
        if kept:
            tails = {
                d: f"{result['face'][d]['kbps']:.1f} kbit/s"
                for d in ("quantised", "mbc_refresh_lowest", "h264_lowest", "av1_lowest")
                if d in result["face"]
            }
            rows.append((f"{clip.name} #{result['kept_frame']}", kept, tails))
    if picture is not None and rows:
        from uma.bench.mbc_picture import save_side_by_side

        save_side_by_side(picture, rows)
        out["picture"] = str(picture)
    out["summary_real_clips"] = summarise(out["clips"], MODEL_OWN)
    return out
