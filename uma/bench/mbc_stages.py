"""`uma bench mbc`'s engine and receiver steps, timed: light and body motion against the
mirror, coding, decoding, and the figures a clip reports about them.

Units: milliseconds per frame (wall clock and this process's CPU time), kbit/s at 25
frames/s, pixels.
"""

from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from uma.bench.timing import warm_up

__all__ = [
    "Clock", "Coded", "encode", "decode", "rates", "tracking", "stages", "median", "warm_model_path",
]  # fmt: skip

SCALED_FPS = 25.0


def median(values: list[float]) -> float | None:
    return round(float(np.median(values)), 3) if values else None


class Clock:
    """Wall-clock and CPU milliseconds per stage, one value per call (`with clock(stage):`).
    CPU time (`time.process_time`, this process's threads) is what a loaded machine cannot
    inflate; wall clock also counts the time other processes held the cores."""

    def __init__(self) -> None:
        self.wall: dict[str, list[float]] = {}
        self.cpu: dict[str, list[float]] = {}
        self.warm_up_s = 0.0  # untimed calls that compiled or loaded kernels (`warm_up`)

    @contextmanager
    def __call__(self, stage: str):
        cpu = time.process_time()  # read outside the wall clock's span: never counted in it
        begin = time.perf_counter()
        yield
        wall_ms = (time.perf_counter() - begin) * 1000.0
        self.add(stage, wall_ms, (time.process_time() - cpu) * 1000.0)

    def add(self, stage: str, wall_ms: float, cpu_ms: float) -> None:
        self.wall.setdefault(stage, []).append(wall_ms)
        self.cpu.setdefault(stage, []).append(cpu_ms)

    def median(self, stage: str, *, cpu: bool = False) -> float | None:
        return median((self.cpu if cpu else self.wall).get(stage, []))


@dataclass
class Coded:
    """What the engine sent for a clip: per tracked frame the light measured against each
    renderer and the body motion, and the packets."""

    lights: dict = field(default_factory=dict)
    other_lights: dict = field(default_factory=dict)
    mixed_lights: dict = field(default_factory=dict)
    bodies: dict = field(default_factory=dict)
    packets: list = field(default_factory=list)
    map_blocks: int = 0  # the block map's window: its changes ride in the packets


def encode(lumas, results, units, stream_config, renderers, clock: Clock) -> Coded:
    """The engine's side: light and body motion against its mirror (and the other renderers'
    light), every set coded with its block map changes (`uma.mbc.map_sender`: the set drawn
    on the mirror, the choice against the source); `clock` gets "light", "body" and
    "map_engine"."""
    from uma.mbc.body import BodyTracker
    from uma.mbc.light import measure_light
    from uma.mbc.map_sender import MapSender
    from uma.mbc.stream import ParameterEncoder

    mirror, other, mixed = renderers
    first = next((i for i, result in enumerate(results) if result), None)
    if first is not None:  # the kernels of light and rendering loaded before any is timed
        clock.warm_up_s += warm_up(
            lambda: warm_model_path(mirror, lumas[first], results[first].params, units.camera)
        )
    sender = MapSender(lumas[0].shape[::-1], SCALED_FPS)  # its rates at 25 frames/s
    encoder, body_tracker, coded = (
        ParameterEncoder(units, stream_config, sender.map_blocks),
        BodyTracker(camera=units.camera),
        Coded(map_blocks=sender.map_blocks),
    )

    def changes(index):
        def chosen(decoded):
            with clock("map_engine"):
                return sender.changes(mirror, units, decoded, lumas[index])

        return chosen

    for index, result in enumerate(results):
        values = None
        if result:
            with clock("light"):
                coded.lights[index] = measure_light(mirror, lumas[index], result.params)
            with clock("body"):
                body_tracker.measure(mirror, lumas[index])  # a failure sends the last good one
                coded.bodies[index] = body_tracker.last
            coded.other_lights[index] = measure_light(other, lumas[index], result.params)
            coded.mixed_lights[index] = measure_light(mixed, lumas[index], result.params)
            values = np.concatenate([result.params, coded.bodies[index], coded.lights[index]])
        packets = encoder.push(index, values, changes(index) if result else None)
        sender.count(packets)
        coded.packets += packets
    coded.packets += encoder.flush()
    return coded


def warm_model_path(mirror, luma, params, camera: bool = False) -> None:
    """Untimed: the light and body motion measured once against `mirror` (on a throwaway
    tracker), and the scene drawn with the head and torso moved (their edges blend); what
    `uma bench mbc` and `uma bench sim` call before timing the model path."""
    from uma.mbc.body import BodyTracker
    from uma.mbc.layers import NO_BODY_MOTION
    from uma.mbc.light import measure_light

    measure_light(mirror, luma, params)
    BodyTracker(camera=camera).measure(mirror, luma)
    moved, body = np.array(params, dtype=np.float64), NO_BODY_MOTION.copy()
    moved[0], body[0] = moved[0] + 3.0, 2.0
    mirror.render(moved, None, body if getattr(mirror, "layered", False) else None)


def decode(units, stream_config, packets, clock: Clock, map_blocks=0, changes=None):
    """Every packet decoded in order: the decoded set per frame and each frame's share of its
    packet's decoding (wall and CPU ms); with `map_blocks` (`Coded.map_blocks`) each frame's
    block map changes go into the dict `changes`."""
    from uma.mbc.decoder import ParameterDecoder

    decoder = ParameterDecoder(units, stream_config, map_blocks)
    decoded: dict[int, np.ndarray] = {}
    shares: dict[int, tuple[float, float]] = {}
    for packet in packets:
        data = packet.to_bytes()
        begin, cpu = time.perf_counter(), time.process_time()
        out = decoder.decode(data)
        n = max(len(out.frames), 1)
        share = (
            (time.perf_counter() - begin) * 1000.0 / n,
            (time.process_time() - cpu) * 1000.0 / n,
        )
        for k, (frame, values) in enumerate(out.frames):
            decoded[frame], shares[frame] = values, share
            if out.changes and changes is not None:
                changes[frame] = out.changes[k]
    return decoded, shares


def rates(lumas, packets, stream_config, scored) -> dict:
    """The stream's size and rates at 25 frames/s."""
    from uma.mbc.packets import IP_UDP_RTP_BYTES

    height, width = lumas[0].shape
    payload_bytes = sum(p.size_bytes for p in packets)
    wire_bytes = payload_bytes + IP_UDP_RTP_BYTES * len(packets)
    seconds = len(lumas) / SCALED_FPS  # the same frames at 25 frames/s
    return {
        "size": f"{width}x{height}",
        "rate_kbps": round(payload_bytes * 8 / seconds / 1000.0, 3),
        "wire_kbps": round(wire_bytes * 8 / seconds / 1000.0, 3),
        "packets": len(packets),
        "frames_per_packet": stream_config.frames_per_packet,
        "payload_bytes_per_frame": round(payload_bytes / len(lumas), 2),
    }


def tracking(results, clock: Clock, mde: list[float]) -> dict:
    """How the tracker did, and its times."""
    reinits = [r for r in results[1:] if r.reinitialised]
    return {
        "reinits": len(reinits),
        "lost_tracks": sum(r.reason.startswith("track lost") for r in reinits),
        "failures": sum(not r for r in results),
        "reinit_reasons": sorted({r.reason.split(" (")[0] for r in reinits}),
        "evaluations_median": median(
            [r.evaluations for r in results[1:] if r and not r.reinitialised]
        ),
        "track_ms_median": clock.median("track"),
        "init_ms_median": clock.median("init"),
        "light_ms_median": clock.median("light"),
        "body_ms_median": clock.median("body"),
        "render_ms_median": clock.median("decode_render"),
        "track_cpu_ms_median": clock.median("track", cpu=True),
        "init_cpu_ms_median": clock.median("init", cpu=True),
        "mde_median_px": round(float(np.median(mde)), 4) if mde else None,
        "mde_p95_px": round(float(np.percentile(mde, 95)), 4) if mde else None,
    }


def stages(clock: Clock, refreshed) -> dict:
    """The model path per frame, stage by stage (medians; the refresh's per frame of the clip
    at the lowest rung): the engine's tracking, light (its measure against the mirror), body
    motion and block map (the mirror's drawing of the decoded set and the choice), the
    receiver's decoding and rendering and its block map, the refresh's coding and
    composition; wall clock and this process's CPU time. The engine's map is the lowest
    rung's refresh engine's when it ran one (its drawing whole on the frames its judge reads:
    the judge's drawing too), else the plain stream's."""
    names = ("track", "light", "body", "map_engine", "decode_render", "block_map")
    refresh = refreshed.get("mbc_refresh_lowest")
    info = refresh[2] if refresh else {}
    wall = {name: clock.median(name) for name in names} | {"refresh": info.get("ms_per_frame")}
    cpu = {name: clock.median(name, cpu=True) for name in names}
    cpu["refresh"] = info.get("cpu_ms_per_frame")
    if info.get("map_engine_ms_median") is not None:
        wall["map_engine"] = info["map_engine_ms_median"]
        cpu["map_engine"] = info["map_engine_cpu_ms_median"]
    return {
        "stages_ms": wall,
        "model_path_ms": round(sum(v for v in wall.values() if v is not None), 3),
        "stages_cpu_ms": cpu,
        "model_path_cpu_ms": round(sum(v for v in cpu.values() if v is not None), 3),
        "kernel_warm_up_s": round(clock.warm_up_s, 3),
    }
