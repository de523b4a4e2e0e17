"""`uma bench mbc`'s model-aided refresh: the MBC stream plus H.264 refresh pictures.

Units: kbit/s at the clip's own frame rate (the parameters and the refresh together, measured
bits), frames per second, pixels.

A display `mbc_refresh_*` spends a rung's rate: the MBC parameter stream, and with what is
left (the rung's rate minus the plain MBC stream's measured payload rate) real libx264 at a
low frame rate, decoded: of the whole picture (`region="frame"`, coded at a given size and
upscaled) or of a fixed-size box around the face (`region="face"`, its position on each
frame sent beside it, 32 bits a unit, counted), pasted with a feathered edge on the receiver's
rendering of that frame. Each refresh picture becomes the receiver's reference, at the pose
the parameter stream decoded for its frame (no pose travels with it), once its bits have
arrived over a channel of the refresh's rate (`uma.mbc.refresh`) and that pose has been
decoded; until the first one the receiver renders from what it held before (the clip's frame
0, as the plain MBC does). Every frame is the scene rendered from the newest reference the
encoder adopted (`RefreshSpec.choose`) at the decoded pose, relit by light measured against
that same reference: the encoder mirrors the
receiver (it knows what it sent and when it arrives) and the receiver replays the same switches.
A refresh frame the tracker found no face on is not coded.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from uma.mbc.refresh_coder import (
    RefreshCoder,
    box_corner,
    even_px,
    face_box_size,
    take_refresh,
)

__all__ = ["RefreshSpec", "DEFAULT_REFRESH", "refresh_display"]


@dataclass(frozen=True)
class RefreshSpec:
    """A refresh: the ladder rung whose total rate it spends, its frame rate, the coded size
    (W, H) of the whole picture (None: the rung's own) or, for `region="face"`, the coded box
    as a fraction `face_scale` of the box (`face_margin` times the model's extent on the first
    tracked frame, a multiple of 16 pixels); whether the face's own triangles come from the
    description's picture (`SceneRenderer.set_face_source`); extra latency; libx264's VBV
    buffer in refresh frame intervals (None: the ladder's); `choose`: the encoder adopts a
    refresh picture only where it is nearer its frame than the encoder's mirror of the
    receiver's rendering there (a flag of one bit a unit, counted), so a worse picture never
    replaces a better reference."""

    rung_index: int
    refresh_fps: float
    size: tuple[int, int] | None = None
    description_face: bool = False
    latency_s: float = 0.0
    vbv_frames: float | None = None
    region: str = "frame"
    face_margin: float = 1.6
    face_scale: float = 1.0
    choose: bool = True


# Chosen on akiyo's and carphone's frames 150-299 (docs/mbc.md), quoted on frames 0-149.
DEFAULT_REFRESH = {
    "mbc_refresh_lowest": RefreshSpec(0, 5.0, region="face", face_scale=0.5),
    "mbc_refresh_second": RefreshSpec(1, 25 / 3, region="face", face_scale=0.5),
}


def _size_label(spec: RefreshSpec) -> str:
    if spec.region == "face":
        return f"{spec.face_scale:g} x box of {spec.face_margin:g} x the model's extent"
    return "x".join(str(v) for v in spec.size) if spec.size else "rung"


def _code_refresh(clip, results, spec, budget_kbps, size):
    """The refresh units and, per unit index, its decoded picture (`RefreshCoder.code`)."""
    from uma.mbc.refresh import RefreshUnit, refresh_frames
    from uma.video import load_ladder

    ladder = load_ladder()
    rung = ladder.rungs[spec.rung_index]
    box, corners = None, {}
    if spec.region == "face":
        model = clip.description.model
        box = face_box_size(model, next(r for r in results if r).params, spec.face_margin, size)
        coded = tuple(even_px(v * spec.face_scale) for v in box)
        corners = {i: box_corner(model, r.params, box, size) for i, r in enumerate(results) if r}
    else:
        coded = spec.size or (rung.width, rung.height)
    settings = ladder.encoder.kwargs()
    if spec.vbv_frames is not None:
        settings["vbv_frames"] = spec.vbv_frames
    coder = RefreshCoder(size, coded, spec.refresh_fps, budget_kbps, settings, box)
    units, pictures = [], {}
    for index in refresh_frames(len(clip.frames), clip.fps, spec.refresh_fps):
        if not results[index]:
            continue  # no pose to place the picture with: not coded
        bits, keyframe, picture = coder.code(clip.frames[index], corners.get(index))
        if picture is not None:
            pictures[len(units)] = picture
        units.append(RefreshUnit(index, bits, keyframe))
    return units, pictures


def refresh_display(
    clip,
    results,
    face_units,
    stream_config,
    mbc_kbps: float,
    spec: RefreshSpec,
    *,
    head_ring: float | None = None,
) -> tuple[list[np.ndarray], float, dict]:
    """Every frame's display (YUV 4:2:0), the total rate (kbit/s) and what the refresh did;
    `results` the tracker's per frame, `mbc_kbps` the plain stream's payload at the clip's
    rate, `head_ring` the receiver's (`SceneRenderer`). With nothing left of the rung's rate
    it is the plain MBC (no refresh unit)."""
    from uma.errors import ConfigError
    from uma.mbc.body import BodyTracker
    from uma.mbc.decoder import ParameterDecoder
    from uma.mbc.light import measure_light
    from uma.mbc.refresh import schedule_refresh
    from uma.mbc.scene_render import SceneRenderer
    from uma.mbc.stream import ParameterEncoder
    from uma.video import load_ladder

    if spec.region not in ("frame", "face"):
        raise ConfigError(f"refresh region: expected 'frame' or 'face', got {spec.region!r}")
    frames = clip.frames
    height, width = frames[0].shape[0] * 2 // 3, frames[0].shape[1]
    budget_kbps = load_ladder().rungs[spec.rung_index].rate_kbps - mbc_kbps
    units, pictures = [], {}
    begin = time.perf_counter()
    if budget_kbps > 1.0:  # libx264 takes whole kbit/s
        units, pictures = _code_refresh(clip, results, spec, budget_kbps, (width, height))
    coding_s = time.perf_counter() - begin
    schedule = schedule_refresh(
        units, len(frames), clip.fps, max(budget_kbps, 1e-9), latency_s=spec.latency_s
    )

    def renderer():
        out = SceneRenderer(clip.description, (width, height), head_ring_outlines=head_ring)
        if results[0]:
            out.set_reference(frames[0], results[0].params)
        out.set_face_source(spec.description_face)
        return out

    def switch(target, k, values):
        """Make unit k's picture `target`'s reference at its frame's decoded pose."""
        take_refresh(target, face_units, values, pictures[k])

    def nearer(k, index, params):
        """Whether unit k's picture is nearer frame `index`'s luma than the mirror's rendering
        (over the face box for a face refresh)."""
        luma = frames[index][:height]
        rendering = mirror.render(params, measure_light(mirror, luma, params))[0][:height]
        if spec.region == "face":
            (x0, y0), patch = pictures[k]
            box_h = patch.shape[0] * 2 // 3
            box = (slice(y0, y0 + box_h), slice(x0, x0 + patch.shape[1]))
            candidate, rendering, luma = patch[:box_h], rendering[box], luma[box]
        else:
            candidate = pictures[k][:height]
        truth = luma.astype(np.float32)
        return float(np.mean((candidate - truth) ** 2)) < float(np.mean((rendering - truth) ** 2))

    # The encoder's mirror: a unit serves once it has arrived and its frame's pose is decoded.
    unit_at = {unit.frame: k for k, unit in enumerate(units)}
    mirror, current, switches, packets, adopted = renderer(), -1, {}, [], set()
    body_tracker = BodyTracker()
    encoder = ParameterEncoder(face_units, stream_config)
    decoder = ParameterDecoder(face_units, stream_config)
    decoded: dict[int, np.ndarray] = {}
    for index, result in enumerate(results):
        k = unit_at.get(index)
        if k in pictures and (not spec.choose or nearer(k, index, result.params)):
            adopted.add(k)  # decided on the unit's own frame, before it can arrive
        k = int(schedule.serving[index])
        while k > current and (k not in adopted or units[k].frame not in decoded):
            k -= 1  # not adopted, or not decoded (yet): the newest usable one before it
        if k > current:
            switches[index] = (k, decoded[units[k].frame])
            switch(mirror, k, decoded[units[k].frame])
            current = k
        values = None
        if result:
            light = measure_light(mirror, frames[index][:height], result.params)
            body = None
            if face_units.body:
                body_tracker.measure(mirror, frames[index][:height])
                body = body_tracker.last
            values = np.concatenate([result.params, [] if body is None else body, light])
        out = encoder.push(index, values)
        out += encoder.flush() if index == len(results) - 1 else []
        for packet in out:
            decoded.update(decoder.decode(packet.to_bytes()).frames)
        packets += out
    receiver, shown, last = renderer(), [], frames[0]
    switch_s = 0.0
    for index in range(len(frames)):
        if index in switches:
            k, values = switches[index]
            begin = time.perf_counter()
            switch(receiver, k, values)
            switch_s += time.perf_counter() - begin
        if index in decoded:
            params, light = face_units.split(decoded[index])
            last, _ = receiver.render(params, light, face_units.body_of(decoded[index]))
        shown.append(last)
    seconds = len(frames) / clip.fps
    params_kbps = sum(p.size_bytes for p in packets) * 8 / seconds / 1000.0
    flag_bits = len(units) if spec.choose else 0
    refresh_kbps = (sum(u.size_bits for u in units) + flag_bits) / seconds / 1000.0
    served = [k for k, _ in switches.values()]
    delays = [i - units[k].frame for i, (k, _) in switches.items()]
    info = {
        "refresh_fps": spec.refresh_fps,
        "region": spec.region,
        "refresh_size": _size_label(spec),
        "description_face": spec.description_face,
        "budget_kbps": round(max(budget_kbps, 0.0), 3),
        "params_kbps": round(params_kbps, 3),
        "refresh_kbps": round(refresh_kbps, 3),
        "units": len(units),
        "adopted": len(adopted),
        "served": len(served),
        "delay_frames_median": float(np.median(delays)) if delays else None,
        "delay_frames_max": int(max(delays)) if delays else None,
        # Encoding and decoding the refresh pictures, and the receiver's taking them (the
        # composition), per frame of the clip: the model path's refresh share.
        "ms_per_frame": round((coding_s + switch_s) * 1000.0 / len(frames), 3),
    }
    return shown, params_kbps + refresh_kbps, info
