"""`uma bench bound`: the least delay each scenario's link allows any engine, frame by frame.

Units: delays in ms, packet sizes in bytes, shares as fractions.

For every capture instant of a scenario (its source's rate over its run), the link alone bounds
the frame's capture-to-display delay from below (`uma.metrics.link_bound`): no engine, rate
control or playout can show that frame, or a newer one, before a packet started at its capture
has crossed the downlink the scenario meets (`uma.sim.world.scenario_link`: the route at the
scenario's seed, handover gaps, outage faults, each technology's one-way delay). The bound is
given per packet size: `HEADER_BYTES` alone (no packet is smaller), a packet of the model codec's
parameters, a full video packet. A target below the p95 bound cannot be met on that scenario.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from uma.config.scenario import Scenario

__all__ = ["PACKET_BYTES", "BoundConfig", "scenario_bound", "run_bound", "format_table"]

# The header alone (IPv4 + UDP + RTP), a model-codec packet of four frames' parameters, and a
# video packet of the Salsify scenario's size.
PACKET_BYTES = (40, 120, 1200)
OVER_S = (1.0, 1.5)


@dataclass(frozen=True)
class BoundConfig:
    scenarios: tuple[Scenario, ...]
    packet_bytes: tuple[int, ...] = PACKET_BYTES
    step_s: float | None = None  # the bound's own choice: 1 ms, coarser for long runs


def source_fps(scenario: Scenario) -> float:
    """The capture rate a run of `scenario` has: a video file's own, else the scenario's."""
    if scenario.source.kind == "file":
        from uma.video import VideoFileSource

        return float(VideoFileSource(scenario.source.path, loop=scenario.source.loop).fps)
    return float(scenario.source.fps)


def scenario_bound(scenario: Scenario, config: BoundConfig) -> dict[str, Any]:
    """One scenario's bounds: per packet size, the p95 and median in ms and shares over 1, 1.5 s."""
    from uma.metrics.link_bound import bound_summary, frame_delay_bounds_s
    from uma.sim.world import scenario_link

    capacity, delay_s_of = scenario_link(scenario)
    fps = source_fps(scenario)
    frames = int(round(scenario.run_duration_s * fps))
    capture_s = np.arange(frames) / fps
    packets = {}
    for size_bytes in config.packet_bytes:
        bounds_s = frame_delay_bounds_s(
            capacity, delay_s_of, capture_s, size_bits=8 * size_bytes, step_s=config.step_s
        )
        packets[str(size_bytes)] = bound_summary(bounds_s, over_s=OVER_S)
    return {
        "seed": scenario.seed,
        "fps": round(fps, 3),
        "frames": frames,
        "duration_s": scenario.run_duration_s,
        "packets": packets,
    }


def run_bound(config: BoundConfig) -> dict[str, Any]:
    """Every scenario's bounds; the JSON object of docs/benchmarks.md."""
    return {
        "packet_bytes": list(config.packet_bytes),
        "scenarios": {s.name: scenario_bound(s, config) for s in config.scenarios},
    }


def format_table(result: dict[str, Any]) -> str:
    """A readable table: per scenario and packet size, the p95 and median bounds."""
    lines = [
        "Least capture-to-display delay the link allows any engine (Salsify's count, per frame)",
        f"{'scenario':<32} {'packet B':>8} {'p95 ms':>8} {'median ms':>9} "
        + " ".join(f"{'>' + format(s, 'g') + ' s':>7}" for s in OVER_S),
    ]
    for name, row in result["scenarios"].items():
        for size, summary in row["packets"].items():
            shares = " ".join(f"{summary['share_over_s'].get(f'{s:g}', 0.0):7.3f}" for s in OVER_S)
            lines.append(
                f"{name:<32} {size:>8} {_ms(summary['delay_p95_ms']):>8} "
                f"{_ms(summary['delay_median_ms']):>9} {shares}"
            )
    return "\n".join(lines) + "\n"


def _ms(value: float | None) -> str:
    return "-" if value is None else f"{value:,.0f}"
