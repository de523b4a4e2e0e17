"""`uma bench mbc`'s model-aided refresh: the MBC stream plus H.264 refresh pictures.

Units: kbit/s at the clip's own frame rate (the parameters and the refresh together, measured
bits), frames per second, pixels.

A display `mbc_refresh_*` spends a rung's rate: the MBC parameter stream, and with what is
left (the rung's rate minus the plain MBC stream's measured payload rate) real libx264 of the
whole picture at a low frame rate and a given size, decoded and upscaled. Each refresh picture
becomes the receiver's reference, with the pose the tracker found on its frame, once its bits
have arrived over a channel of the refresh's rate (`uma.mbc.refresh`); until the first one
the receiver renders from what it held before (the clip's frame 0, as the plain MBC does).
Every frame is the scene rendered from the newest reference at the decoded pose, relit by
light measured against that same reference (the encoder mirrors the schedule, which it knows:
it sent the units). A refresh frame the tracker found no face on is not used as a reference.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["RefreshSpec", "DEFAULT_REFRESH", "refresh_display"]


@dataclass(frozen=True)
class RefreshSpec:
    """A refresh: the ladder rung whose total rate it spends, its frame rate, the coded size
    (W, H; None: the rung's own), whether the face's own triangles come from the description's
    picture (`SceneRenderer.set_face_source`) rather than the refresh picture, extra latency."""

    rung_index: int
    refresh_fps: float
    size: tuple[int, int] | None = None
    description_face: bool = False
    latency_s: float = 0.0


# Chosen on akiyo's and carphone's frames 150-299 (docs/mbc.md), quoted on frames 0-149.
DEFAULT_REFRESH = {
    "mbc_refresh_lowest": RefreshSpec(0, 2.5, (176, 144)),
    "mbc_refresh_second": RefreshSpec(1, 2.5, (176, 144)),
}


def _code_refresh(frames, fps, spec, budget_kbps, size):
    """The refresh units and their decoded pictures (index -> picture at the source size)."""
    from uma.mbc.refresh import RefreshUnit, refresh_frames
    from uma.video import H264Decoder, H264Encoder, load_ladder, resize_yuv420

    ladder = load_ladder()
    rung = ladder.rungs[spec.rung_index]
    coded_w, coded_h = spec.size or (rung.width, rung.height)
    width, height = size
    encoder = H264Encoder(
        coded_w, coded_h, spec.refresh_fps, budget_kbps, **ladder.encoder.kwargs()
    )
    decoder = H264Decoder()
    units, pictures = [], {}
    for index in refresh_frames(len(frames), fps, spec.refresh_fps):
        unit = encoder.encode(resize_yuv420(frames[index], coded_w, coded_h))
        picture = decoder.decode(unit.data)
        if picture is not None:
            pictures[len(units)] = resize_yuv420(picture, width, height)
        units.append(RefreshUnit(index, unit.size_bits, unit.is_keyframe))
    return units, pictures, rung


def refresh_display(
    clip, results, face_units, stream_config, mbc_kbps: float, spec: RefreshSpec
) -> tuple[list[np.ndarray], float, dict]:
    """Every frame's display (YUV 4:2:0), the total rate (kbit/s) and what the refresh did;
    `results` the tracker's per frame, `mbc_kbps` the plain stream's payload at the clip's
    rate. With nothing left of the rung's rate it is the plain MBC (no refresh unit)."""
    from uma.mbc.decoder import ParameterDecoder
    from uma.mbc.light import measure_light
    from uma.mbc.refresh import schedule_refresh
    from uma.mbc.scene_render import SceneRenderer
    from uma.mbc.stream import ParameterEncoder
    from uma.video import load_ladder

    frames = clip.frames
    height, width = frames[0].shape[0] * 2 // 3, frames[0].shape[1]
    budget_kbps = load_ladder().rungs[spec.rung_index].rate_kbps - mbc_kbps
    units, pictures = [], {}
    if budget_kbps > 1.0:  # libx264 takes whole kbit/s
        units, pictures, _ = _code_refresh(frames, clip.fps, spec, budget_kbps, (width, height))
    schedule = schedule_refresh(
        units, len(frames), clip.fps, max(budget_kbps, 1e-9), latency_s=spec.latency_s
    )

    def renderer():
        out = SceneRenderer(clip.description, (width, height))
        if results[0]:
            out.set_reference(frames[0], results[0].params)
        out.set_face_source(spec.description_face)
        return out

    def follow(target, index, current):
        """Switch `target` to the reference serving `index`; the reference index now held."""
        k = int(schedule.serving[index])
        if k != current and k in pictures and results[units[k].frame]:
            target.set_reference(pictures[k], results[units[k].frame].params)
            return k
        return current

    mirror, current, packets = renderer(), -1, []
    encoder = ParameterEncoder(face_units, stream_config)
    for index, result in enumerate(results):
        current = follow(mirror, index, current)
        values = None
        if result:
            light = measure_light(mirror, frames[index][:height], result.params)
            values = np.append(result.params, light)
        packets += encoder.push(index, values)
    packets += encoder.flush()
    decoder = ParameterDecoder(face_units, stream_config)
    decoded = {}
    for packet in packets:
        decoded.update(decoder.decode(packet.to_bytes()).frames)
    receiver, current, shown, last = renderer(), -1, [], frames[0]
    for index in range(len(frames)):
        current = follow(receiver, index, current)
        if index in decoded:
            params, light = face_units.split(decoded[index])
            last, _ = receiver.render(params, light)
        shown.append(last)
    seconds = len(frames) / clip.fps
    params_kbps = sum(p.size_bytes for p in packets) * 8 / seconds / 1000.0
    refresh_kbps = sum(u.size_bits for u in units) / seconds / 1000.0
    delays = schedule.delay_frames()
    info = {
        "refresh_fps": spec.refresh_fps,
        "refresh_size": "x".join(str(v) for v in spec.size) if spec.size else "rung",
        "description_face": spec.description_face,
        "budget_kbps": round(max(budget_kbps, 0.0), 3),
        "params_kbps": round(params_kbps, 3),
        "refresh_kbps": round(refresh_kbps, 3),
        "units": len(units),
        "served": int((schedule.serves_from >= 0).sum()),
        "delay_frames_median": float(np.median(delays)) if len(delays) else None,
        "delay_frames_max": int(delays.max()) if len(delays) else None,
    }
    return shown, params_kbps + refresh_kbps, info
