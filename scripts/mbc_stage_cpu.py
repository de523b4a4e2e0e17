"""CPU milliseconds per frame of each model-path stage, with only `uma.mbc`'s public objects.

    PYTHONPATH=CHECKOUT python scripts/mbc_stage_cpu.py [--frames N] [--bench]

runs on any checkout that has them (so two trees compare side by side in one run: call it
alternately with each on `PYTHONPATH`) and prints one JSON object: per CIF clip (the talking
head, akiyo) the median CPU ms (`time.process_time`) of tracking, light against the mirror,
body motion, and decoding plus the receiver's rendering, and their sum (the refresh not
included). Frame 0 (the initialisation) is not counted. With `--bench`, per clip also
`uma bench mbc`'s own figures for it (`uma.bench.mbc.run_clip`, the lowest rung's refresh
only): every stage's CPU median, the model path's CPU sum, and the refresh's judge, the
mirror's takes and the engine's map there.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import json
import time

import numpy as np


def _median_ms(values: list[float]) -> float:
    return round(1000.0 * float(np.median(values)), 3)


def stages(clip) -> dict[str, float]:
    """The clip's per-stage medians (ms) and their sum."""
    from uma.mbc.body import BodyTracker
    from uma.mbc.decoder import ParameterDecoder
    from uma.mbc.encoder import FaceTracker
    from uma.mbc.light import measure_light
    from uma.mbc.scene_render import SceneRenderer
    from uma.mbc.stream import ParameterEncoder, StreamConfig
    from uma.mbc.units import FaceUnits

    height, width = clip.frames[0].shape[0] * 2 // 3, clip.frames[0].shape[1]
    lumas = [f[:height] for f in clip.frames]
    FaceTracker(clip.description, rng=0).track(lumas[0])  # numba loads its kernels
    tracker = FaceTracker(clip.description, rng=0)
    times: dict[str, list[float]] = {"track": [], "light": [], "body": [], "decode_render": []}
    results = []
    for index, luma in enumerate(lumas):
        begin = time.process_time()
        results.append(tracker.track(luma, frame=index))
        if index:
            times["track"].append(time.process_time() - begin)
    mirror, receiver = (SceneRenderer(clip.description, (width, height)) for _ in range(2))
    for renderer in (mirror, receiver):
        renderer.set_reference(clip.frames[0], results[0].params)
    units = FaceUnits.of(clip.description.model, clip.description.params, light=True, body=True)
    encoder, decoder = ParameterEncoder(units, StreamConfig()), ParameterDecoder(units)
    body, packets = BodyTracker(), []
    for index, luma in enumerate(lumas):
        params = results[index].params
        begin = time.process_time()
        light = measure_light(mirror, luma, params)
        times["light"].append(time.process_time() - begin)
        begin = time.process_time()
        body.measure(mirror, luma)
        times["body"].append(time.process_time() - begin)
        packets += encoder.push(index, np.concatenate([params, body.last, light]))
    packets += encoder.flush()
    for packet in packets:
        begin = time.process_time()
        out = decoder.decode(packet.to_bytes())
        share = (time.process_time() - begin) / max(len(out.frames), 1)
        for _, values in out.frames:
            begin = time.process_time()
            geometry, light = units.split(values)
            receiver.render(geometry, light, units.body_of(values))
            times["decode_render"].append(share + time.process_time() - begin)
    out = {name: _median_ms(values) for name, values in times.items()}
    out["sum"] = round(sum(out.values()), 3)
    return out


def bench(clip) -> dict:
    """`uma bench mbc`'s model path figures for `clip` (CPU ms; the refresh's parts wall ms a
    frame of the clip, as the bench reports them)."""
    from uma.bench.mbc import run_clip
    from uma.bench.mbc_refresh import DEFAULT_REFRESH

    name = "mbc_refresh_lowest"
    out = run_clip(clip, refresh={name: DEFAULT_REFRESH[name]})
    refresh = out["refresh"][name]
    parts = ("judge_ms_per_frame", "mirror_take_ms_per_frame", "receiver_take_ms_per_frame",
             "map_engine_cpu_ms_median", "adopted", "served")  # fmt: skip
    return {
        "stages_cpu_ms": out["stages_cpu_ms"],
        "model_path_cpu_ms": out["model_path_cpu_ms"],
        "plain_map_engine_cpu_ms": out["block_map"]["engine_cpu_ms_median"],
        **{key: refresh.get(key) for key in parts},
    }


def main() -> None:
    from uma.bench.mbc_clips import default_clips

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=100, help="frames a clip (default 100)")
    parser.add_argument("--bench", action="store_true", help="also `uma bench mbc`'s figures")
    args = parser.parse_args()
    clips = [c for c in default_clips(args.frames) if c.name in ("talking-head", "akiyo")]
    out = {clip.name: stages(clip) for clip in clips}
    if args.bench:
        for clip in clips:
            out[clip.name]["bench"] = bench(clip)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
