"""`uma bench mbc`'s refresh engine: the simulation's engine for one clip, with its block map.

Units: frames (indices into the clip), seconds, milliseconds, bits.

The engine codes every frame's set against its mirror, which takes each refresh the receiver
takes; it chooses the block map's changes on that mirror (`uma.mbc.map_sender`, the stream's
map at both ends, as `uma.sim.mbc_codecs` keeps it) and judges each refresh unit against it.
On a frame the judge reads, the map's drawing is the mirror's whole picture, kept
(`MapSender.changes`' `whole`): the frame's one drawing, which the judge, and the mirror's take
of that refresh later, are handed instead of drawing the same set again.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from uma.bench.mbc_stages import SCALED_FPS
from uma.mbc.refresh_coder import take_refresh

__all__ = ["Engine", "run_engine"]


@dataclass
class Engine:
    """What the engine sent and what its map cost: the packets, the decoded sets and the map's
    changes by frame, the refreshes each frame's receiver takes (frame -> [(unit, its decoded
    set), ...]), and the map's (wall ms, CPU ms) per frame it ran."""

    packets: list = field(default_factory=list)
    decoded: dict = field(default_factory=dict)
    changes: dict = field(default_factory=dict)
    switches: dict = field(default_factory=dict)
    map_ms: list = field(default_factory=list)


def set_of(mirror, face_units, body_tracker, frame: np.ndarray, params: np.ndarray):
    """The set the encoder codes for `frame`: geometry, body motion and light against the
    mirror."""
    from uma.mbc.light import measure_light

    height = mirror.size[1]
    light = measure_light(mirror, frame[:height], params)
    body = []
    if face_units.body:
        body_tracker.measure(mirror, frame[:height])
        body = body_tracker.last
    return np.concatenate([params, body, light])


def _chooser(engine: Engine, map_sender, mirror, face_units, luma, whole: bool):
    """The stream's callback for one frame: the map's changes on `mirror`, timed."""

    def chosen(decoded):
        begin, cpu = time.perf_counter(), time.process_time()
        out = map_sender.changes(mirror, face_units, decoded, luma, whole=whole)
        wall_ms = (time.perf_counter() - begin) * 1000.0
        engine.map_ms.append((wall_ms, (time.process_time() - cpu) * 1000.0))
        return out

    return chosen


def run_engine(clip, results, face_units, stream_config, sender, mirror) -> Engine:
    """The encoder's side: every frame's set coded with its map's changes against `mirror`,
    which takes refreshes as the receiver does; `sender` (`uma.bench.mbc_refresh`'s) codes
    each refresh unit on its frame and judges it (`sender.judges`)."""
    from uma.mbc.body import BodyTracker
    from uma.mbc.decoder import ParameterDecoder
    from uma.mbc.map_sender import MapSender
    from uma.mbc.stream import ParameterEncoder

    engine = Engine()
    body_tracker = BodyTracker(camera=face_units.camera)
    map_sender = MapSender(mirror.size, SCALED_FPS)  # its rates at 25 frames/s, as the bench's
    encoder = ParameterEncoder(face_units, stream_config, map_sender.map_blocks)
    decoder = ParameterDecoder(face_units, stream_config, map_sender.map_blocks)
    height = mirror.size[1]
    for index, result in enumerate(results):
        taken = sender.due(index, engine.decoded)
        if taken:
            engine.switches[index] = [(k, engine.decoded[sender.units[k].frame]) for k in taken]
            begin, cpu = time.perf_counter(), time.process_time()
            for k, values in engine.switches[index]:
                take_refresh(mirror, face_units, values, sender.pictures[k])
            sender.add_mirror_time(begin, cpu)
        values, chosen = None, None
        if result:
            frame = clip.frames[index]
            values = set_of(mirror, face_units, body_tracker, frame, result.params)
            luma = frame[:height]
            chosen = _chooser(engine, map_sender, mirror, face_units, luma, sender.judges(index))
        out = encoder.push(index, values, chosen)
        out += encoder.flush() if index == len(results) - 1 else []
        map_sender.count(out)
        for packet in out:
            got = decoder.decode(packet.to_bytes())
            for k, (decoded_frame, decoded_values) in enumerate(got.frames):
                engine.decoded[decoded_frame] = decoded_values
                if got.changes:
                    engine.changes[decoded_frame] = got.changes[k]
        engine.packets += out
        if values is not None:  # decided on the unit's own frame, before it can arrive
            sender.code(index, mirror, encoder.decoded)
    return engine
