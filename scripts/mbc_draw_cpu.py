"""CPU milliseconds of the model path's two drawings a frame, with only `uma.mbc`'s public objects.

    PYTHONPATH=CHECKOUT python scripts/mbc_draw_cpu.py [--frames N] [--passes P] [--clips A,B]

runs on any checkout that has them (so two trees compare side by side: call it alternately
with each on `PYTHONPATH`) and prints one JSON object: per clip the median CPU ms
(`time.process_time`) of the receiver's drawing of each decoded set (YUV, as `uma bench mbc`'s
`decode_render` draws it, without the decoding) and of the engine's mirror drawing the same
set for its block map (luma only, the map's read box: `map_engine`'s drawing, without the
choice), and a digest of every picture drawn (two trees that draw the same pictures print the
same digests). Each pass draws the clip's sets on fresh renderers (nothing kept from the last
pass); the medians are over every frame of every pass. The sets are the tracker's poses
coded and decoded as the bench's plain stream (light against the mirror, body motion).
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import hashlib
import json
import time

import numpy as np


def _decoded_sets(clip, results, units, mirror) -> list[np.ndarray]:
    """Every tracked frame's set (pose, body motion, light) coded and decoded, in order."""
    from uma.mbc.body import BodyTracker
    from uma.mbc.decoder import ParameterDecoder
    from uma.mbc.light import measure_light
    from uma.mbc.stream import ParameterEncoder, StreamConfig

    height = mirror.size[1]
    encoder, decoder = ParameterEncoder(units, StreamConfig()), ParameterDecoder(units)
    body, packets = BodyTracker(camera=units.camera), []
    for index, result in enumerate(results):
        if not result:
            continue
        luma = clip.frames[index][:height]
        light = measure_light(mirror, luma, result.params)
        body.measure(mirror, luma)
        packets += encoder.push(index, np.concatenate([result.params, body.last, light]))
    packets += encoder.flush()
    return [values for p in packets for _, values in decoder.decode(p.to_bytes()).frames]


def _renderers(clip, first, size):
    from uma.config.codecs import MbcConfig
    from uma.mbc.profile import profile_renderer

    receiver = profile_renderer(clip.description, size, MbcConfig())
    mirror = profile_renderer(clip.description, size, MbcConfig())
    mirror.set_luma_only(True)
    for renderer in (receiver, mirror):
        renderer.set_reference(clip.frames[0], first)
    return receiver, mirror


def drawings(clip, passes: int) -> dict:
    """The clip's median CPU ms a drawing (receiver, mirror) and the pictures' digests."""
    from uma.mbc.block_map import BlockMap
    from uma.mbc.encoder import FaceTracker
    from uma.mbc.units import FaceUnits

    height, width = clip.frames[0].shape[0] * 2 // 3, clip.frames[0].shape[1]
    size = (width, height)
    tracker = FaceTracker(clip.description, rng=0)
    results = [tracker.track(f[:height], frame=i) for i, f in enumerate(clip.frames)]
    first = next(r for r in results if r)
    units = FaceUnits.of(clip.description.model, clip.description.params, light=True, body=True)
    sets = _decoded_sets(clip, results, units, _renderers(clip, first.params, size)[1])
    times: dict[str, list[float]] = {"receiver": [], "mirror": []}
    digests = {name: hashlib.sha256() for name in times}
    for k in range(passes):
        receiver, mirror = _renderers(clip, first.params, size)
        box = BlockMap(size, 25.0).read_box
        for values in sets:
            params, light = units.split(values)
            body = units.body_of(values)
            begin = time.process_time()
            shown, face = receiver.render(params, light, body)
            times["receiver"].append(time.process_time() - begin)
            begin = time.process_time()
            drawn, _ = mirror.render(params, light, body, luma_only=True, only=box)
            times["mirror"].append(time.process_time() - begin)
            if k == 0:
                digests["receiver"].update(shown.tobytes() + face.tobytes())
                window = box(face)
                if window is not None:
                    x0, y0, x1, y1 = window
                    digests["mirror"].update(np.ascontiguousarray(drawn[y0:y1, x0:x1]).tobytes())
    out = {name: round(1000.0 * float(np.median(v)), 3) for name, v in times.items()}
    out["sets"] = len(sets)
    out["digests"] = {name: d.hexdigest()[:16] for name, d in digests.items()}
    return out


def main() -> None:
    from uma.bench.mbc_clips import default_clips

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=100, help="frames a clip (default 100)")
    parser.add_argument("--passes", type=int, default=3, help="passes a clip (default 3)")
    parser.add_argument("--clips", default="talking-head,akiyo", help="comma-separated names")
    args = parser.parse_args()
    names = args.clips.split(",")
    clips = [c for c in default_clips(args.frames) if c.name in names]
    print(json.dumps({clip.name: drawings(clip, args.passes) for clip in clips}))


if __name__ == "__main__":
    main()
