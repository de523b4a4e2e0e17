"""`uma bench mbc`'s model-aided refresh: the MBC stream plus H.264 refresh pictures.

Units: kbit/s at the clip's own frame rate (the parameters and the refresh together, measured
bits), frames per second, pixels.

A display `mbc_refresh_*` spends a rung's rate: the MBC parameter stream, and with what is
left (the rung's rate minus the plain MBC stream's measured payload rate) real libx264 (or
another full-frame codec of the registry, `RefreshSpec.codec`) at a lower frame rate, decoded: of the whole picture (`region="frame"`, coded at a given size and
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
A refresh frame the tracker found no face on is not coded. The parameter stream carries the
block map's changes, chosen on that same mirror and taken by the receiver, as the simulation's
(`uma.bench.mbc_refresh_engine`): the map's drawing of a judged frame is the judge's too.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from uma.bench.mbc_refresh_engine import run_engine
from uma.bench.mbc_refresh_receiver import UnitsIn, receive
from uma.bench.mbc_stages import median
from uma.mbc.refresh_coder import (
    REFRESH_CODEC,
    RefreshCoder,
    box_corner,
    even_px,
    face_box_size,
    take_refresh,
)

__all__ = ["RefreshSpec", "DEFAULT_REFRESH", "PREVIOUS_REFRESH", "refresh_display"]


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
    replaces a better reference. `region="residual"` codes the face box's residual against
    the engine's rendering (`uma.mbc.refresh_coder`), `intra_every_unit` with an IDR every
    unit; `codec` the full-frame codec of the registry that codes the refresh (`h264`, `vp8`,
    `av1`: its own ladder's encoder settings), `preset` its preset (libx264's name or
    SVT-AV1's number; None: the ladder's); `rate_gain` scales the rate the encoder is asked
    for over the budget (its rate control undershoots at these sizes; the channel the units
    cross stays the budget)."""

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
    intra_every_unit: bool = False
    preset: str | int | None = None
    codec: str = REFRESH_CODEC
    rate_gain: float = 1.0


# Chosen on akiyo's and carphone's frames 150-299 (docs/refresh.md), quoted on frames 0-149,
# foreman and carphone_qcif: libx264 at its medium preset (the simulation's
# `engine.mbc.refresh.preset`), the face box at 0.625 of its size, 12.5 frames/s at both rungs,
# a VBV of 2 frames: how fresh a refresh is matters more than its bits (docs/refresh.md, session
# refresh2); SVT-AV1 and VP8 there do no better.
REFRESH_PRESET = "medium"
REFRESH_FPS = 12.5
REFRESH_SCALE = 0.625
REFRESH_VBV_FRAMES = 2.0
DEFAULT_REFRESH = {
    name: RefreshSpec(
        rung,
        REFRESH_FPS,
        region="face",
        face_scale=REFRESH_SCALE,
        preset=REFRESH_PRESET,
        vbv_frames=REFRESH_VBV_FRAMES,
    )  # fmt: skip
    for name, rung in (("mbc_refresh_lowest", 0), ("mbc_refresh_second", 1))
}
# The default until session refresh2: half the box, the rung's frame rate, the ladder's VBV.
PREVIOUS_REFRESH = {
    "mbc_refresh_lowest": RefreshSpec(0, 5.0, region="face", face_scale=0.5, preset=REFRESH_PRESET),
    "mbc_refresh_second": RefreshSpec(
        1, 25 / 3, region="face", face_scale=0.5, preset=REFRESH_PRESET
    ),
}


def _size_label(spec: RefreshSpec) -> str:
    if spec.region == "face":
        return f"{spec.face_scale:g} x box of {spec.face_margin:g} x the model's extent"
    return "x".join(str(v) for v in spec.size) if spec.size else "rung"


def _coder(clip, results, spec, budget_kbps, size):
    """The refresh's `RefreshCoder` and the box's corner per tracked frame (face regions)."""
    from uma.video import default_ladder_path, load_ladder

    ladder = load_ladder(default_ladder_path(spec.codec))
    rung = ladder.rungs[spec.rung_index]
    box, corners = None, {}
    if spec.region in ("face", "residual"):
        model = clip.description.model
        box = face_box_size(model, next(r for r in results if r).params, spec.face_margin, size)
        coded = tuple(even_px(v * spec.face_scale) for v in box)
        corners = {i: box_corner(model, r.params, box, size) for i, r in enumerate(results) if r}
    else:
        coded = spec.size or (rung.width, rung.height)
    settings = ladder.encoder.kwargs()
    if spec.vbv_frames is not None:
        settings["vbv_frames"] = spec.vbv_frames
    if spec.intra_every_unit:
        settings["keyint_frames"] = 1
    if spec.preset is not None:
        settings["preset"] = spec.preset
    rate_kbps = budget_kbps * spec.rate_gain
    coder = RefreshCoder(size, coded, spec.refresh_fps, rate_kbps, settings, box, spec.codec)
    return coder, corners


def _renderer(clip, results, spec, size, profile, luma_only=False):
    """The receiver's renderer (and the encoder's mirror of it, `luma_only`) before any
    refresh, as the codec's `profile` (the `engine.mbc` section) describes it."""
    from uma.mbc.profile import profile_renderer

    out = profile_renderer(clip.description, size, profile)
    out.set_luma_only(luma_only)
    if results[0]:
        out.set_reference(clip.frames[0], results[0].params)
    out.set_face_source(spec.description_face)
    return out


def _nearer(mirror, face_units, spec, frame, values, picture, base=None) -> bool:
    """Whether a refresh's decoded `picture` is nearer `frame` than the mirror's rendering at
    `values` (the set decoded for that frame): over the box for a face refresh, the judge the
    simulation uses (`uma.mbc.refresh_gain_db`), over the picture's luma otherwise; a
    residual's composed box against `base`, the rendering it was coded against."""
    from uma.mbc.refresh_judge import refresh_gain_db, residual_gain_db

    if base is not None:
        return residual_gain_db(base, picture, frame) > 0.0
    if spec.region == "face":
        corner, patch = picture
        return refresh_gain_db(mirror, face_units, values, corner, patch, frame) > 0.0
    height = mirror.size[1]
    params, light = face_units.split(values)
    body = face_units.body_of(values)
    rendering = mirror.render(params, light, body, luma_only=True)[0][:height]
    truth = frame[:height].astype(np.float32)
    candidate = picture[:height]
    return float(np.mean((candidate - truth) ** 2)) < float(np.mean((rendering - truth) ** 2))


class _Sender:
    """The encoder's side of the refresh: it codes a refresh unit on each refresh frame inside
    the render loop, adopts it or not (`RefreshSpec.choose`), and says which adopted units
    the receiver takes on a frame (after their arrival, once their frame's set is decoded).
    A residual is coded against `ahead`, the receiver's renderer as it will be when it takes
    the unit (every adopted unit taken in order, at once); `mirror` lags as the receiver."""

    def __init__(self, clip, face_units, spec, coder, corners, budget_kbps, ahead):
        from uma.mbc.refresh import refresh_frames

        self.clip, self.face_units, self.spec = clip, face_units, spec
        self.coder, self.corners, self.budget_kbps, self.ahead = coder, corners, budget_kbps, ahead
        self.at = set()
        if coder is not None:
            self.at = set(refresh_frames(len(clip.frames), clip.fps, spec.refresh_fps))
        self.units, self.pictures, self.adopted, self.current = [], {}, set(), -1
        self.sent = []  # per unit: its bytes and its box's corner (None: the whole picture)
        self.seconds = [0.0, 0.0]  # wall, CPU spent coding (and, for a residual, `ahead`)
        self.judge_seconds = [0.0, 0.0]  # wall, CPU spent judging (the mirror's drawing)
        self.mirror_seconds = [0.0, 0.0]  # wall, CPU the mirror spent taking refreshes
        self._serving, self._scheduled = None, -1

    def schedule(self):
        from uma.mbc.refresh import schedule_refresh

        clip, rate_kbps = self.clip, max(self.budget_kbps, 1e-9)
        return schedule_refresh(
            self.units, len(clip.frames), clip.fps, rate_kbps, latency_s=self.spec.latency_s
        )

    def units_in(self) -> UnitsIn:
        """The receiver's refresh stream: every unit sent, decoded by its own decoder once it
        has arrived."""
        arrived = self.schedule().serves_from if self.coder is not None else []
        return UnitsIn(self.coder, self.sent, arrived, self.spec.region == "residual")

    def judges(self, index: int) -> bool:
        """Whether a unit coded on frame `index` is judged against the mirror at its decoded
        set (`code`): the engine's map then draws the mirror's whole picture for it."""
        return index in self.at and self.spec.choose and self.spec.region != "residual"

    def add_mirror_time(self, begin: float, cpu: float) -> None:
        """The mirror's taking refreshes since (`begin`, `cpu`) counted."""
        _add(self.mirror_seconds, begin, cpu)

    def due(self, index: int, decoded) -> list[int]:
        """The units the receiver takes on frame `index`: the newest adopted one that has
        arrived and whose frame's set is decoded (a residual: with every adopted one before)."""
        if self._scheduled != len(self.units):  # units coded so far: all before this frame
            self._serving, self._scheduled = self.schedule().serving, len(self.units)
        k = int(self._serving[index])
        while k > self.current and (k not in self.adopted or self.units[k].frame not in decoded):
            k -= 1
        if k <= self.current:
            return []
        taken = [k]
        if self.spec.region == "residual":
            taken = [j for j in range(self.current + 1, k + 1) if j in self.adopted]
        self.current = k
        return taken

    def code(self, index: int, mirror, values: np.ndarray) -> None:
        """Code frame `index`'s refresh unit if it is a refresh frame; adopt it if it beats the
        mirror's drawing of `values`, its set as decoded (the simulation's judge)."""
        from uma.mbc.refresh import RefreshUnit

        if index not in self.at:
            return
        frame, units = self.clip.frames[index], self.face_units
        begin, cpu = time.perf_counter(), time.process_time()
        base = None
        if self.spec.region == "residual":
            params, light = units.split(values)
            base = self.ahead.render(params, light, units.body_of(values))[0]
        bits, keyframe, picture = self.coder.code(frame, self.corners.get(index), base=base)
        k = len(self.units)
        self.units.append(RefreshUnit(index, bits, keyframe))
        self.sent.append((self.coder.data, self.corners.get(index)))  # what the receiver gets
        _add(self.seconds, begin, cpu)
        if picture is None:
            return
        self.pictures[k] = picture
        begin, cpu = time.perf_counter(), time.process_time()
        nearer = not self.spec.choose or _nearer(mirror, units, self.spec, frame, values, picture,
                                                 base)  # fmt: skip
        _add(self.judge_seconds, begin, cpu)
        if nearer:
            self.adopted.add(k)
            if base is not None:
                begin, cpu = time.perf_counter(), time.process_time()
                take_refresh(self.ahead, units, values, picture)
                _add(self.seconds, begin, cpu)


def _add(seconds: list[float], begin: float, cpu: float) -> None:
    """Wall and CPU seconds since (`begin`, `cpu`) added to `seconds`."""
    seconds[0] += time.perf_counter() - begin
    seconds[1] += time.process_time() - cpu


def refresh_display(
    clip,
    results,
    face_units,
    stream_config,
    model_kbps: float,
    spec: RefreshSpec,
    *,
    profile=None,
) -> tuple[list[np.ndarray], float, dict]:
    """Every frame's display (YUV 4:2:0), the total rate (kbit/s) and what the refresh did;
    `results` the tracker's per frame, `model_kbps` the plain stream's payload at the clip's
    rate, `profile` the `engine.mbc` section the receiver renders as (None: its defaults).
    With nothing left of the rung's rate it is the plain MBC (no refresh unit)."""
    from uma.config.codecs import MbcConfig
    from uma.errors import ConfigError
    from uma.video import load_ladder

    profile = MbcConfig() if profile is None else profile
    if spec.region not in ("frame", "face", "residual"):
        raise ConfigError(
            f"refresh region: expected 'frame', 'face' or 'residual', got {spec.region!r}"
        )
    frames = clip.frames
    size = (frames[0].shape[1], frames[0].shape[0] * 2 // 3)
    budget_kbps = load_ladder().rungs[spec.rung_index].rate_kbps - model_kbps
    coder, corners = None, {}
    if budget_kbps > 1.0:  # libx264 takes whole kbit/s
        coder, corners = _coder(clip, results, spec, budget_kbps, size)
    ahead = _renderer(clip, results, spec, size, profile) if spec.region == "residual" else None
    sender = _Sender(clip, face_units, spec, coder, corners, budget_kbps, ahead)
    mirror = _renderer(clip, results, spec, size, profile, luma_only=True)
    engine = run_engine(clip, results, face_units, stream_config, sender, mirror)
    if coder is not None:
        coder.close()  # one SVT-AV1 encoder open at a time in a process
    receiver = _renderer(clip, results, spec, size, profile)
    shown, switch_s, switch_cpu_s = receive(receiver, face_units, frames[0], len(frames), engine,
                                            sender.units_in())  # fmt: skip
    seconds = len(frames) / clip.fps
    params_kbps = sum(p.size_bytes for p in engine.packets) * 8 / seconds / 1000.0
    units, flag_bits = sender.units, len(sender.units) if spec.choose else 0
    refresh_kbps = (sum(u.size_bits for u in units) + flag_bits) / seconds / 1000.0
    info = _info(spec, budget_kbps, params_kbps, refresh_kbps, units, sender.adopted, engine)
    # The engine's mirror (luma only) and the receiver took the same refreshes: the same luma.
    info["mirror_is_receiver"] = np.array_equal(mirror.reference[: size[1]],
                                                receiver.reference[: size[1]])  # fmt: skip
    # Encoding and decoding the refresh pictures (for a residual, the engine's rendering it is
    # coded against), the receiver's decoding and taking the units, per frame of the clip: the
    # model path's refresh share; the engine's judging and its mirror's takes too, and apart.
    spent = (sender.seconds, sender.judge_seconds, sender.mirror_seconds)
    wall, cpu = (sum(s[k] for s in spent) for k in (0, 1))
    info["ms_per_frame"] = round((wall + switch_s) * 1000.0 / len(frames), 3)
    info["cpu_ms_per_frame"] = round((cpu + switch_cpu_s) * 1000.0 / len(frames), 3)
    info["judge_ms_per_frame"] = round(sender.judge_seconds[0] * 1000.0 / len(frames), 3)
    info["mirror_take_ms_per_frame"] = round(sender.mirror_seconds[0] * 1000.0 / len(frames), 3)
    info["receiver_take_ms_per_frame"] = round(switch_s * 1000.0 / len(frames), 3)
    # The engine's map on this mirror (its drawing whole on a judged frame: the judge's too).
    for key, k in (("map_engine_ms_median", 0), ("map_engine_cpu_ms_median", 1)):
        info[key] = median([ms[k] for ms in engine.map_ms])
    return shown, params_kbps + refresh_kbps, info


def _info(spec, budget_kbps, params_kbps, refresh_kbps, units, adopted, engine) -> dict:
    """What the refresh did, for the bench's JSON."""
    switches = engine.switches
    delays = [i - units[k].frame for i, taken in switches.items() for k, _ in taken]
    return {
        "refresh_fps": spec.refresh_fps,
        "region": spec.region,
        "codec": spec.codec,
        "refresh_size": _size_label(spec),
        "description_face": spec.description_face,
        "budget_kbps": round(max(budget_kbps, 0.0), 3),
        "params_kbps": round(params_kbps, 3),
        "refresh_kbps": round(refresh_kbps, 3),
        "units": len(units),
        "adopted": len(adopted),
        "served": sum(len(taken) for taken in switches.values()),
        "delay_frames_median": float(np.median(delays)) if delays else None,
        "delay_frames_max": int(max(delays)) if delays else None,
    }
