"""`uma bench sim`: the whole simulation against the bare codec and metric work it contains.

Units: wall-clock seconds (`_s`), measured with `time.perf_counter` in this process only.

The source's frames are prepared first (a camera gives them for free; synthesising the talking
head is not simulation work), then the simulation of the scenario is timed (with `codec`, on
that full-frame codec's ladder). Then, in the same process, exactly the codec work
it did is redone without SimPy: the sender's encode of every frame, the engine's decode and its
re-encode of the frames it sent (same rungs, same IDRs), the receiver's decode of the frames it
decoded; and, apart, the same quality metrics on the same (source, displayed) pairs.
`ratio` = sim_s / (codec_s + metrics_s): what the simulation adds around the unavoidable work.

The sender's uplink stream and the engine's decode of it are the same in every run of a given
source and sender setting, so (with `reuse_uplink`, the default) they are computed once before
anything is timed (`uplink_s`, counted in neither `sim_s` nor `codec_s`), as a sweep or the
headline computes them once for all their runs, and both the simulation and its replay take
them from that memo (`uma.sim.uplink`; results byte for byte the same).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from uma.bench.timing import kernel_signatures, kernels_loaded_since, warm_up
from uma.config.scenario import Scenario
from uma.experiments.uplink_store import StoreSettings

__all__ = ["SimBenchConfig", "run_sim_bench", "format_table", "warm_kernels"]


@dataclass(frozen=True)
class SimBenchConfig:
    scenario: Scenario
    frames: int
    width: int
    height: int
    video: str | None = None
    codec: str | None = None  # the full-frame codec (`engine.codec`); None: the scenario's
    reuse_uplink: bool = True  # the sender's stream computed once, untimed (`uplink_s`)
    # where that stream is kept between processes (`uma.experiments.uplink_store`; None: not)
    store: StoreSettings | None = None


def _prepare(config: SimBenchConfig) -> Scenario:
    scenario = config.scenario
    source = scenario.source
    if config.video is not None:
        source = source.model_copy(update={"kind": "file", "path": config.video, "loop": True})
    else:
        source = source.model_copy(update={"width": config.width, "height": config.height})
    duration_s = config.frames / source.fps
    update = {"source": source, "duration_s": duration_s}
    if config.codec is not None and config.codec != scenario.engine.codec:
        # Another codec's run: its own ladder file, not the scenario's.
        engine = scenario.engine.model_dump() | {"codec": config.codec, "ladder": None}
        update["engine"] = type(scenario.engine).model_validate(engine)
    return scenario.model_copy(update=update)


class _ListSource:
    """The source's first frames (and a synthetic source's ground truth of each), read
    before timing."""

    def __init__(self, frames: list, source) -> None:
        self._frames = frames
        self.fps, self.width, self.height = source.fps, source.width, source.height
        self.name, self.frame_count = source.name, len(frames)
        self.description = getattr(source, "description", None)  # the talking head's, for MBC
        from uma.face.region import face_mode

        # The run's face boxes, as the source itself would give them. A synthetic source's
        # ground truth (the talking head's pose and points) comes with each frame it draws:
        # kept with the frames, read before timing, like them.
        self.face_mode = face_mode(source)
        truth = getattr(source, "ground_truth", None)
        self._truths = [truth(index) for index in range(len(frames))] if truth else []
        self._source_truth = truth
        self.ground_truth = self._ground_truth if truth else None
        self.clip_frames = getattr(source, "clip_frames", None)

    def _ground_truth(self, index: int) -> dict:
        if index < len(self._truths):
            return self._truths[index]
        return self._source_truth(index)

    def frames(self):
        return iter(self._frames)


def _prepared_source(scenario: Scenario, frames: int) -> _ListSource:
    from uma.sim.sources import open_source

    source = open_source(scenario.source, seed=scenario.seed)
    iterator = iter(source.frames())
    return _ListSource([next(iterator) for _ in range(frames)], source)


def _chain(scenario: Scenario, result, source: _ListSource, memo):
    """A codec chain as the run's (its registry, ladder and points), timing its codecs."""
    from uma.sim.codecs import CodecChain
    from uma.sim.points import ladder_path
    from uma.video import load_ladder

    return CodecChain(
        scenario,
        load_ladder(ladder_path(scenario)),
        result.points,
        width=source.width,
        height=source.height,
        fps=result.fps,
        account=True,
        description=result.description.content,
        uplink=memo,
    )


def _recode(chain, log, index: int, picture: np.ndarray) -> dict[int, np.ndarray]:
    """The engine's coding of frame `index` as the run sent it (same rung, same IDR) and the
    receiver's decoding of what the run decoded; {frame: picture} decoded."""
    from uma.sim.packets import EncodedUnit

    rung = int(log["rung"][index])
    coded = []
    if chain.engine_point not in (-1, rung):
        coded.append(chain.engine_flush())  # MBC's open packet, leaving MBC
    coded.append(
        chain.engine_encode(picture, rung, force_idr=bool(log["keyframe"][index]), frame=index)
    )
    decoded: dict[int, np.ndarray] = {}
    for out in coded:
        if out is None or not out.data:
            continue  # buffered for MBC's next packet, or nothing left
        carried = out.frames or (index,)
        if not log["decoded"][carried[-1]]:
            continue
        unit = EncodedUnit(
            unit_seq=index,
            frame=carried[-1],
            codec=str(log["codec"][carried[-1]]),
            rung=rung,
            width=0,
            height=0,
            keyframe=out.keyframe,
            data=out.data,
            frames=out.frames,
        )
        decoded.update(chain.receiver_decode(unit))
    return decoded


def _replay(scenario: Scenario, result, source: _ListSource, memo) -> tuple[float, float, dict]:
    """Redo the run's codec work and metrics alone, through the same codec registry and chain
    as the run (every codec it used: the full-frame codec, and MBC's initialisations, tracking,
    coding and rendering); returns (codec_s, metrics_s, codec seconds per codec)."""
    from uma.codecs import Role
    from uma.engine.points import role_indices
    from uma.sim.quality import QualityMeter

    log = result.log
    chain = _chain(scenario, result, source, memo)
    model = role_indices(result.points, Role.MODEL)
    inits = set(result.model.init_frames)
    # The bare metric work, one plane pair after another on one core.
    serial = scenario.metrics.model_copy(update={"workers": 0})
    meter = QualityMeter(serial, width=source.width, height=source.height)
    decoded: dict[int, np.ndarray] = {}
    frames = iter(source.frames())
    for index in range(log.frames):
        frame = next(frames)
        encoded = chain.sender_encode(frame)
        # Selection: the sender's tracking and the engine's decoding of its parameters.
        chain.engine_receive_side(chain.sender_side_data(frame, index), index)
        picture = chain.engine_decode(encoded)
        if index in inits and picture is not None and model:
            chain.initialise_model(picture, model[0], frame=index)
        if log["sent"][index] and picture is not None:
            decoded.update(_recode(chain, log, index, picture))
        shown = int(log["shown_frame"][index])
        box = result.face_boxes[index] if index < len(result.face_boxes) else None
        meter.submit(index, frame, shown, decoded.get(shown), box=box)
        for old in [k for k in decoded if k < shown]:
            del decoded[old]
    return chain.seconds, meter.seconds, dict(chain.codec_seconds)


def _warm_kernels(scenario: Scenario, source: _ListSource) -> None:
    """Untimed calls that reach every compiled kernel the run and its replay may call, with
    the types they use: a frame's and a face box's scores and, when the run may switch to the
    model codec, the tracker's initialisation and tracking, the receiver's rendering, the
    light against the engine's mirror and the body motion."""
    from uma.metrics.quality import frame_scores
    from uma.sim.points import model_description

    if not source._frames:
        return
    frame = source._frames[0]
    height, width = frame.shape[0] * 2 // 3, frame.shape[1]
    luma = frame[:height]
    frame_scores(luma, luma)
    description, _ = model_description(scenario, source)
    if description is None:
        return
    from uma.bench.mbc_stages import warm_model_path
    from uma.mbc import FaceTracker
    from uma.sim.mbc_codecs import scene_renderer

    tracker = FaceTracker(description, rng=0)
    result = tracker.track(luma)
    tracker.track(luma, frame=1)
    if not result:
        return
    renderer = scene_renderer(description, (width, height))
    renderer.set_reference(frame, result.params)
    renderer.render(result.params)
    warm_model_path(renderer, luma, result.params)


def warm_kernels(scenario: Scenario, *, width: int, height: int, frames: int) -> None:
    """Compile or load every kernel a run of `scenario` at `width` x `height` may call: the
    bench's own warm-up on the first `frames` of its source (`uma.bench.warm`)."""
    config = SimBenchConfig(scenario, frames, width, height)
    prepared = _prepare(config)
    _warm_kernels(prepared, _prepared_source(prepared, frames))


def _uplink(scenario: Scenario, source: _ListSource, store: StoreSettings | None):
    """The sender's stream and the engine's decode of it, computed once (or read from the
    on-disk store, and kept in memory for the run and its replay): (memo, seconds)."""
    from uma.experiments.uplink_store import UplinkStore
    from uma.sim.coders import compute_uplink
    from uma.sim.uplink import UplinkMemo

    memo = UplinkMemo() if store is None else UplinkStore(store, in_memory=True)
    start = time.perf_counter()
    compute_uplink(memo, scenario, source._frames, width=source.width, height=source.height,
                   fps=float(source.fps))  # fmt: skip
    return memo, time.perf_counter() - start


def run_sim_bench(config: SimBenchConfig) -> dict[str, Any]:
    """Time the simulation and its bare codec and metric work; keys in docs/benchmarks.md."""
    from uma.sim import run_scenario

    scenario = _prepare(config)
    source = _prepared_source(scenario, config.frames)
    warm_up_s = warm_up(lambda: _warm_kernels(scenario, source))
    memo, uplink_s, stored = None, 0.0, None
    if config.reuse_uplink:
        memo, uplink_s = _uplink(scenario, source, config.store)
        stored = memo.hits if config.store is not None else None
    kernels = kernel_signatures()
    start = time.perf_counter()
    result = run_scenario(scenario, account=True, source=source, uplink=memo)
    sim_s = time.perf_counter() - start
    codec_s, metrics_s, per_codec = _replay(scenario, result, source, memo)
    loaded_timed = kernels_loaded_since(kernels)
    simulated_s = result.duration_s
    return {
        "frames": int(result.log.frames),
        "video": f"{result.width}x{result.height}@{result.fps:g}",
        "scenario": scenario.name,
        "codec": scenario.engine.codec,
        "sim_s": round(sim_s, 3),
        "codec_s": round(codec_s, 3),
        "metrics_s": round(metrics_s, 3),
        "ratio": round(sim_s / (codec_s + metrics_s), 3),
        "realtime_x": round(simulated_s / sim_s, 2),
        "simulated_s": round(simulated_s, 3),
        "split_in_sim_s": {
            "codec": round(result.codec_s, 3),
            "metrics_threads": round(result.metrics_s, 3),
            "main_besides_codec": round(sim_s - result.codec_s, 3),
        },
        "metric_workers": scenario.metrics.workers,
        # numba's kernels compiled (or loaded from their cache) before timing, untimed; and
        # any the timed run or replay still compiled or loaded (none when the warm-up covers
        # every path they take).
        "warm_up_s": round(warm_up_s, 3),
        "kernels_loaded_timed": loaded_timed,
        # The sender's stream and its decode, computed once before timing (0: not reused).
        "uplink_reused": memo is not None,
        "uplink_s": round(uplink_s, 3),
        # frames of it read from the on-disk store (None: no store, UMA_CACHE=off)
        "uplink_stored_frames": stored,
        # The codecs the run used and the replay timed (`codec_s` split by codec).
        "codecs": sorted(set(result.codec_seconds or {}) | set(per_codec)),
        "codec_s_by_codec": {name: round(sec, 3) for name, sec in sorted(per_codec.items())},
    }


def format_table(result: dict[str, Any]) -> str:
    split = result["split_in_sim_s"]
    rows = [
        f"uma bench sim: {result['scenario']}, {result['frames']} frames of {result['video']}"
        f", {result['codec']}"
        f" ({result['simulated_s']} s simulated)",
        "",
        f"  {'whole simulation':<34}{result['sim_s']:>9.3f} s",
        f"    {'codecs (main thread)':<32}{split['codec']:>9.3f} s",
        f"    {'SimPy, links, waiting (main)':<32}{split['main_besides_codec']:>9.3f} s",
        f"    {'metrics, summed over threads':<32}{split['metrics_threads']:>9.3f} s"
        f"  ({result['metric_workers']} threads beside the main one)",
        f"  {'same codec work alone':<34}{result['codec_s']:>9.3f} s",
        f"  {'sender stream, computed once':<34}{result['uplink_s']:>9.3f} s"
        f"  ({'reused by both, untimed' if result['uplink_reused'] else 'not reused'})",
        f"  {'same metrics alone':<34}{result['metrics_s']:>9.3f} s",
        f"  {'kernels compiled or loaded':<34}{result['warm_up_s']:>9.3f} s"
        f"  (before timing; {len(result['kernels_loaded_timed'])} more while timed)",
        "",
        f"  ratio sim / (codec + metrics)     {result['ratio']:>9.3f}   (target <= 1.3)",
        f"  faster than real time             {result['realtime_x']:>9.2f}x  (target >= 12 at CIF, idle)",
    ]
    return "\n".join(rows)
