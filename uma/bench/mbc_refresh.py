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
_POSITION_BITS = 32  # a face box's position, two 16-bit numbers a unit
_FEATHER_PX = 8


def _size_label(spec: RefreshSpec) -> str:
    if spec.region == "face":
        return f"{spec.face_scale:g} x box of {spec.face_margin:g} x the model's extent"
    return "x".join(str(v) for v in spec.size) if spec.size else "rung"


def _even(value: float) -> int:
    return max(2, int(round(value / 2)) * 2)


def _face_boxes(clip, results, spec, size):
    """The face box's size (W, H) and, per frame with a face, its corner (x0, y0), even."""
    from uma.face.geometry import project

    width, height = size
    model = clip.description.model
    first = next(r for r in results if r)
    extent = np.ptp(project(model, first.params), axis=0) * spec.face_margin
    box_w, box_h = (min(int(np.ceil(v / 16)) * 16, limit) for v, limit in
                    zip(extent, (width, height), strict=True))  # fmt: skip
    corners = {}
    for index, result in enumerate(results):
        if result:
            centre = project(model, result.params).mean(axis=0)
            x0 = min(max(_even(centre[0] - box_w / 2), 0), width - box_w)
            y0 = min(max(_even(centre[1] - box_h / 2), 0), height - box_h)
            corners[index] = (x0, y0)
    return (box_w, box_h), corners


def _crop(frame: np.ndarray, x0: int, y0: int, box_w: int, box_h: int) -> np.ndarray:
    """The box of a YUV 4:2:0 picture as a YUV 4:2:0 picture (corner and size even)."""
    from uma.video import split_planes

    y, u, v = split_planes(frame)
    out = np.empty((box_h * 3 // 2, box_w), np.uint8)
    out[:box_h] = y[y0 : y0 + box_h, x0 : x0 + box_w]
    chroma = out[box_h:].reshape(2, box_h // 2, box_w // 2)
    for plane, source in zip(chroma, (u, v), strict=True):
        plane[:] = source[y0 // 2 : (y0 + box_h) // 2, x0 // 2 : (x0 + box_w) // 2]
    return out


def _paste(canvas: np.ndarray, patch: np.ndarray, x0: int, y0: int) -> np.ndarray:
    """`canvas` (YUV 4:2:0) with `patch` (YUV 4:2:0) at (x0, y0), its edge feathered into it
    over `_FEATHER_PX` so no seam shows where the older picture goes on."""
    height, width = canvas.shape[0] * 2 // 3, canvas.shape[1]
    box_h, box_w = patch.shape[0] * 2 // 3, patch.shape[1]

    def ramp(n: int) -> np.ndarray:
        k = np.arange(n, dtype=np.float32)
        return np.clip(np.minimum(k + 1, n - k) / _FEATHER_PX, 0.0, 1.0)

    weight = np.outer(ramp(box_h), ramp(box_w))
    out = canvas.copy()
    luma = out[:height, x0 : x0 + box_w][y0 : y0 + box_h]
    luma[:] = np.rint(weight * patch[:box_h] + (1 - weight) * luma)
    half = weight[0::2, 0::2]
    chroma = out[height:].reshape(2, height // 2, width // 2)
    patch_chroma = patch[box_h:].reshape(2, box_h // 2, box_w // 2)
    for plane, source in zip(chroma, patch_chroma, strict=True):
        box = plane[y0 // 2 : y0 // 2 + box_h // 2, x0 // 2 : x0 // 2 + box_w // 2]
        box[:] = np.rint(half * source + (1 - half) * box)
    return out


def _code_refresh(clip, results, spec, budget_kbps, size):
    """The refresh units and, per unit index, its decoded picture: the whole picture at the
    source size, or (corner, box picture) for the face region."""
    from uma.mbc.refresh import RefreshUnit, refresh_frames
    from uma.video import H264Decoder, H264Encoder, load_ladder, resize_yuv420

    ladder = load_ladder()
    rung = ladder.rungs[spec.rung_index]
    width, height = size
    if spec.region == "face":
        (box_w, box_h), corners = _face_boxes(clip, results, spec, size)
        coded_w, coded_h = _even(box_w * spec.face_scale), _even(box_h * spec.face_scale)
    else:
        corners = None
        coded_w, coded_h = spec.size or (rung.width, rung.height)
    settings = ladder.encoder.kwargs()
    if spec.vbv_frames is not None:
        settings["vbv_frames"] = spec.vbv_frames
    encoder = H264Encoder(coded_w, coded_h, spec.refresh_fps, budget_kbps, **settings)
    decoder = H264Decoder()
    units, pictures = [], {}
    for index in refresh_frames(len(clip.frames), clip.fps, spec.refresh_fps):
        if not results[index]:
            continue  # no pose to place the picture with: not coded
        frame, extra_bits = clip.frames[index], 0
        if corners is not None:
            frame, extra_bits = _crop(frame, *corners[index], box_w, box_h), _POSITION_BITS
        unit = encoder.encode(resize_yuv420(frame, coded_w, coded_h))
        picture = decoder.decode(unit.data)
        if picture is not None:
            if corners is None:
                pictures[len(units)] = resize_yuv420(picture, width, height)
            else:
                pictures[len(units)] = (corners[index], resize_yuv420(picture, box_w, box_h))
        units.append(RefreshUnit(index, unit.size_bits + extra_bits, unit.is_keyframe))
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
        picture, fresh = pictures[k], None
        params, light = face_units.split(values)
        if spec.region == "face":  # on the scene as the receiver drew it at that pose
            (x0, y0), patch = picture
            drawn = target.render(params, light, face_units.body_of(values))[0]
            picture = _paste(drawn, patch, x0, y0)
            fresh = np.zeros((height, width), bool)
            fresh[y0 : y0 + patch.shape[0] * 2 // 3, x0 : x0 + patch.shape[1]] = True
        target.set_reference(picture, params, fresh)

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
