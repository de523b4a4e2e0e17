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
from uma.bench.mbc_stages import Clock, decode, encode, rates, stages, tracking
from uma.bench.mbc_table import format_table, summarise
from uma.codecs import full_frame_names, spec
from uma.mbc.block_map import BlockMap

__all__ = [
    "ClipSpec",
    "run_model_bench",
    "format_table",
    "default_clips",
    "file_clip",
    "talking_head_clip",
    "DISPLAYS",
]

BASE_DISPLAYS = (
    "unquantised",
    "quantised",
    "unmapped",
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
MODEL_OWN = "model's own rendering"
# Whether the stream carries the camera's motion (`uma.mbc.camera`): off, held at zero on every
# shipped clip and 0.02-0.04 kbit/s dearer (docs/mbc.md, session mbc4).
CAMERA_MOTION = False
LARGEST_MOTION = -1  # `run_clip(keep_frame=)`: keep the frame of the largest head motion


def _full_frame_codecs() -> list[str]:
    """The registry's full-frame codecs, the uplink's (the one every figure is held against)
    first, then by name."""
    return sorted(full_frame_names(), key=lambda name: (not spec(name).uplink, name))


def _luma(frame: np.ndarray) -> np.ndarray:
    return frame[: frame.shape[0] * 2 // 3]


def _track(clip: ClipSpec, lumas: list[np.ndarray], seed: int, tracker_config, clock: Clock):
    """Every frame's `TrackResult` or `TrackFailure`; `clock` gets "track" and "init"."""
    from uma.mbc.encoder import FaceTracker, TrackerConfig

    # One untimed initialisation first: numba loads its compiled kernels on first use.
    FaceTracker(clip.description, rng=seed).track(lumas[0])
    tracker = FaceTracker(clip.description, config=tracker_config or TrackerConfig(), rng=seed)
    results = []
    for index, picture in enumerate(lumas):
        begin, cpu = time.perf_counter(), time.process_time()
        result = tracker.track(picture, frame=index)
        kind = "init" if result.reinitialised else "track"
        clock.add(
            kind, (time.perf_counter() - begin) * 1000.0, (time.process_time() - cpu) * 1000.0
        )
        results.append(result)
    return results


def _largest_motion(results) -> int:
    """The frame whose tracked head lies farthest from frame 0's (the first tracked one's)."""
    tracked = [(i, r.params) for i, r in enumerate(results) if r]
    if len(tracked) < 2:
        return len(results) - 1
    first = tracked[0][1]
    return max(tracked[1:], key=lambda item: float(np.hypot(*(item[1][:2] - first[:2]))))[0]


def _renderer(clip: ClipSpec, reference: str, first, size, profile):
    """The receiver's renderer as the codec's `profile` (the `engine.mbc` section) describes
    it, as the simulation's: from the last full picture (frame 0, at the pose tracked on it)
    or from the description's own picture."""
    from uma.mbc.profile import profile_renderer

    renderer = profile_renderer(clip.description, size, profile)
    if reference == "picture" and first:
        renderer.set_reference(clip.frames[0], first.params)
    return renderer


def _full_frame_displays(clip: ClipSpec) -> dict:
    """Every full-frame codec at the ladder's two lowest rungs, shown at once and on arrival:
    name -> (pictures, kbit/s, rung)."""
    from uma.bench.mbc_scores import codec_display

    return {
        f"{codec}_{rung_name}{'_delayed' if late else ''}": codec_display(
            clip.frames, clip.fps, rung, codec, delayed=late
        )
        for codec in _full_frame_codecs()
        for rung_name, rung in (("lowest", 0), ("second", 1))
        for late in (False, True)
    }


def _as_decoded(first, units, stream_config):
    """Frame 0's track result at the pose the stream decodes for it (its intra set): the
    receiver knows the reference picture's pose only so, and both ends place the model on the
    reference there (as the simulation's `MbcUnitDecoder` does), so a decoded set equal to
    frame 0's draws the reference itself."""
    from dataclasses import replace

    from uma.mbc.layers import N_BODY, N_TORSO, NO_BODY_MOTION
    from uma.mbc.light import NEUTRAL_LIGHT
    from uma.mbc.stream import ParameterEncoder

    if not first:
        return first
    encoder = ParameterEncoder(units, stream_config)
    still = NO_BODY_MOTION[: N_BODY if units.camera else N_TORSO]
    encoder.push(0, np.concatenate([first.params, still, NEUTRAL_LIGHT]))
    return replace(first, params=units.split(encoder.decoded)[0])


def _renderers(clip: ClipSpec, results, reference: str, profile):
    """The encoder's mirror, the same stream's rendering from the other reference, the
    simulation's choice (the scene from the picture, the face from the description), the
    receiver, and its twin for the scores' own drawings (the unquantised set, the truth's
    mask): the receiver draws only what a receiver draws, so what it keeps between frames
    (the torso layer, the scene's points) is a receiver's."""
    size = (clip.frames[0].shape[1], clip.frames[0].shape[0] * 2 // 3)
    mirror = _renderer(clip, reference, results[0], size, profile)
    other_kind = "description" if reference == "picture" else "picture"
    other = _renderer(clip, other_kind, results[0], size, profile)
    mixed = _renderer(clip, "picture", results[0], size, profile)
    mixed.set_face_source(True)
    receiver, scorer = (_renderer(clip, reference, results[0], size, profile) for _ in range(2))
    return mirror, other, mixed, receiver, scorer


def _check_tracked(clip: ClipSpec, results) -> None:
    from uma.errors import VideoError

    if not any(results):
        reasons = {r.reason.split(": ", 1)[-1] for r in results}
        raise VideoError(
            f"{clip.where or clip.name}: no face tracked in any of {len(results)} frames "
            f"({'; '.join(sorted(reasons)[:2])})"
        )


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
    camera: bool = CAMERA_MOTION,
    profile=None,
) -> dict:
    """Code one clip and score it; see the module docstring. `refresh` names the
    `mbc_refresh_*` displays (`uma.bench.mbc_refresh.RefreshSpec` by name; default
    `DEFAULT_REFRESH`); `camera`: the stream carries the camera's motion; `profile`: the
    `engine.mbc` section whose renderer the receiver uses (None: its defaults, as a run's)."""
    from uma.bench.mbc_refresh import refresh_display
    from uma.config.codecs import MbcConfig
    from uma.mbc.stream import StreamConfig
    from uma.mbc.units import FaceUnits

    stream_config = stream_config or StreamConfig()
    lumas = [_luma(f) for f in clip.frames]
    clock = Clock()
    results = _track(clip, lumas, seed, tracker_config, clock)
    if keep_frame == LARGEST_MOTION:
        keep_frame = _largest_motion(results)
    _check_tracked(clip, results)
    # The encoder's mirror of the receiver: its light is measured against what it will show.
    units = FaceUnits.of(clip.description.model, clip.description.params, light=True, body=True,
                         camera=camera)  # fmt: skip
    results[0] = _as_decoded(results[0], units, stream_config)
    profile = MbcConfig() if profile is None else profile
    # The ring the clip's description carries (its sender's choice), else the profile's.
    ring = clip.description.head_ring_outlines or profile.head_ring_outlines
    *renderers, receiver, scorer = _renderers(clip, results, reference, profile)
    coded = encode(lumas, results, units, stream_config, renderers, clock)
    decoded, shares = decode(units, stream_config, coded.packets, clock, coded.map_blocks,
                             map_changes := {})  # fmt: skip
    displays = _full_frame_displays(clip)
    # The refresh spends the rung's rate minus the plain stream's, both at the clip's own rate.
    refresh = DEFAULT_REFRESH if refresh is None else refresh
    model_clip_kbps = sum(p.size_bytes for p in coded.packets) * 8 / (len(lumas) / clip.fps) / 1000
    refreshed = {name: refresh_display(clip, results, units, stream_config, model_clip_kbps, spec,
                                       profile=profile) for name, spec in refresh.items()}  # fmt: skip
    scored = _score(clip, results, units, coded, (decoded, shares, map_changes),
                    (receiver, *renderers[1:], scorer), displays, refreshed, clock, keep_frame,
                    kept)  # fmt: skip
    # Frame 0 untracked: every renderer drew from the description's own picture (`_renderer`).
    drawn_from = reference if results[0] else "description"
    out = {"frames": len(lumas), "kept_frame": keep_frame, "reference": drawn_from,
           "head_ring_outlines": ring, "fps": round(clip.fps, 3)}  # fmt: skip
    out.update(rates(lumas, coded.packets, stream_config, scored))
    out.update(tracking(results, clock, scored["mde"]))
    out.update(stages(clock, refreshed))
    out.update(_scored(out["rate_kbps"], scored["sums"], displays, refreshed, scored["map"]))
    out["block_map"] = scored["map"]
    return out


def _scored(rate_kbps: float, sums, displays, refreshed, block_map: dict) -> dict:
    """Every display's means per region (with its rate), the codecs' rungs, the refreshes'
    figures, and the quantisation's loss on the face."""
    display_kbps = {"unquantised": None, "quantised": rate_kbps, "frozen": 0.0,
                    "unmapped": rate_kbps - block_map["kbps"],
                    "other_reference": rate_kbps, "description_face": rate_kbps,
                    **{name: displays[name][1] for name in displays},
                    **{name: refreshed[name][1] for name in refreshed}}  # fmt: skip
    means = {name: region_sums.means(display_kbps[name]) for name, region_sums in sums.items()}
    out = {
        **{f"{c}_{r}": {"rung": displays[f"{c}_{r}"][2]}
           for c in _full_frame_codecs() for r in ("lowest", "second")},
        "refresh": {name: refreshed[name][2] for name in refreshed},
        **{region: {d: means[d][region] for d in means} for region in REGIONS},
    }  # fmt: skip
    face = out["face"]
    out["psnr_loss_db"] = round(face["unquantised"]["psnr_db"] - face["unmapped"]["psnr_db"], 3)
    return out


def _score(clip, results, units, coded, received, renderers, displays, refreshed,
           clock, keep_frame, kept) -> dict:  # fmt: skip
    """Every display of every frame but the first scored; the receiver's rendering timed
    ("decode_render": its share of decoding and its drawing); `kept` gets frame `keep_frame`'s
    pictures. {"sums": display -> `RegionSums`, "mde": [px per frame with ground truth]}."""
    from uma.bench.mbc_scores import RegionSums, face_box
    from uma.face.geometry import project
    from uma.fit.mde import mde_px

    receiver, other, mixed, scorer = renderers
    decoded, shares, map_changes = received
    names = BASE_DISPLAYS + tuple(refreshed)
    sums = {d: RegionSums() for d in names}
    shown = {d: clip.frames[0] for d in ("unquantised", "quantised", "other_reference",
                                         "description_face", "unmapped")}  # fmt: skip
    height = clip.frames[0].shape[0] * 2 // 3
    model_mask = np.zeros((height, clip.frames[0].shape[1]), bool)
    mde, box = [], None
    block_map = BlockMap((clip.frames[0].shape[1], height), SCALED_FPS)  # rates at 25 frames/s
    for index, result in enumerate(results):
        if result:  # no face: the last good picture stays (no mask in the wrong place)
            shown["unquantised"], model_mask = scorer.render(
                result.params, coded.lights[index], coded.bodies[index]
            )
        if index in decoded:
            face = _render_decoded(index, decoded[index], shares[index], units, coded, shown,
                                   (receiver, other, mixed), clock)  # fmt: skip
            with clock("block_map"):  # the receiver takes the stream's changes
                shown["quantised"] = block_map.step_with(
                    receiver, shown["unmapped"], face, changes=map_changes.get(index)
                )
        truth_points = None
        if clip.truth is not None:
            truth = clip.truth(index)
            truth_points = project(clip.description.model, truth)
            if result:
                mde.append(mde_px(clip.description.model, result.params, truth))
            _, model_mask = scorer.render(truth)
        box = face_box(clip.frames[index][:height], truth_points, box)
        if index == 0:
            continue
        pictures = dict(shown, frozen=clip.frames[0],
                        **{name: displays[name][0][index] for name in displays},
                        **{name: refreshed[name][0][index] for name in refreshed})  # fmt: skip
        for name in names:
            sums[name].add(clip.frames[index], pictures[name], box, model_mask)
        if kept is not None and index == keep_frame:
            kept.update(pictures, source=clip.frames[index])
    return {"sums": sums, "mde": mde, "map": _map_figures(block_map, len(results), clock)}


def _map_figures(block_map, frames: int, clock) -> dict:
    """The block map's bits (kbit/s at 25 frames/s, as the stream's `rates`: inside its
    packets) and times: the receiver's taking and drawing ("ms_median") and the engine's
    mirror drawing and choice ("engine_ms_median")."""
    kbps = block_map.bits / (frames / SCALED_FPS) / 1000.0
    return {"kbps": round(kbps, 3), "bits": block_map.bits, "changes": block_map.changes,
            "ms_median": clock.median("block_map"),
            "cpu_ms_median": clock.median("block_map", cpu=True),
            "engine_ms_median": clock.median("map_engine"),
            "engine_cpu_ms_median": clock.median("map_engine", cpu=True)}  # fmt: skip


def _render_decoded(index, values, share, units, coded, shown, renderers, clock) -> np.ndarray:
    """The decoded set of frame `index` drawn by the receiver (timed with its decoding share)
    and by the other two renderers, into `shown`; the receiver's face mask."""
    receiver, other, mixed = renderers
    begin, cpu = time.perf_counter(), time.process_time()
    params, light = units.split(values)
    body = units.body_of(values)
    shown["unmapped"], face = receiver.render(params, light, body)
    wall_ms = share[0] + (time.perf_counter() - begin) * 1000.0
    clock.add("decode_render", wall_ms, share[1] + (time.process_time() - cpu) * 1000.0)
    shown["other_reference"], _ = other.render(params, coded.other_lights[index])
    shown["description_face"], _ = mixed.render(params, coded.mixed_lights[index], body)
    return face


def run_model_bench(
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
