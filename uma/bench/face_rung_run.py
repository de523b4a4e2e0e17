"""Whole runs with the face-region rung, and the face detector's modelled cost.

Units: seconds of route, kbit/s, PSNR in dB, detector cost in microseconds per scanned pixel.

`run_three_ways` runs the simulation on a WLAN-then-GSM route with a real clip as source, three
ways: H.264 only, H.264 with the face-region rungs, and switching to the model-based codec (the
clip's description made from `codecs/face/CLIP.yaml`), and reports the GSM stretch.
`detector_cost` measures the detector's CPU time per pixel it scans (CPU time because the machine
is shared). `uma bench face-rung --run CLIP` and `--cost` call them.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from uma.bench.face_rung import CLIPS, face_config, load_clip

__all__ = ["detector_cost", "run_three_ways"]


def detector_cost(frames: int) -> dict[str, Any]:
    """CPU microseconds per scanned pixel of `detect_box` on akiyo, carphone, the talking head."""
    from uma.face import TalkingHeadSource
    from uma.sim.face_region import detect_box, detect_pixels

    out: dict[str, Any] = {}
    clips = [(name, load_clip(name, frames)[1]) for name in CLIPS]
    talking = TalkingHeadSource(width=176, height=144, fps=25, seed=1).frames()
    clips.append(("talking-head", [next(talking) for _ in range(frames)]))
    for name, pictures in clips:
        size = (pictures[0].shape[1], pictures[0].shape[0] * 2 // 3)
        spent = []
        for picture in pictures:
            start = time.process_time()
            detect_box(picture)
            spent.append(time.process_time() - start)
        median_us = float(np.median(spent)) * 1e6
        out[name] = {
            "size": f"{size[0]}x{size[1]}",
            "detect_ms_median": round(median_us / 1000.0, 2),
            "us_per_pixel": round(median_us / detect_pixels(size), 3),
        }
    out["us_per_pixel_median"] = round(
        float(np.median([v["us_per_pixel"] for v in out.values()])), 3
    )
    return out


def run_three_ways(
    name: str,
    *,
    wlan_s: float = 4.0,
    gsm_s: float = 16.0,
    rungs: list[str] | None = None,
    model: bool = True,
    max_backlog_ms: float | None = None,
    policy: str = "oracle",
) -> dict[str, Any]:
    """The whole simulation with the clip as source, WLAN then GSM, three engines."""
    import tempfile

    from uma.codecs import Role, metric_key, model_names, names, spec, uplink_name
    from uma.face.clip import load_points
    from uma.mbc.profile import describe_clip_with_ring
    from uma.paths import codecs_dir
    from uma.sim import run_scenario
    from uma.sim.summary import run_metrics

    _, _, path = load_clip(name, 1)
    out: dict[str, Any] = {
        "clip": path,
        "route": f"WLAN {wlan_s:g} s, GSM {gsm_s:g} s",
        "policy": policy,
    }
    with tempfile.TemporaryDirectory() as tmp:
        face_file = Path(tmp) / f"{name}.face"
        if model:
            points = load_points(codecs_dir() / "face" / f"{name}.yaml")
            describe_clip_with_ring(points).save(face_file)  # as `uma describe` writes it
        region, model_codec = spec(names(Role.REGION)[0]), spec(model_names()[0])
        engines = {
            uplink_name(): {},
            metric_key(region.name): {
                region.config_section: face_config(rungs).model_dump(mode="json")
            },
            model_codec.name: {
                "switching": {"policy": "threshold", "min_dwell_ms": 1000.0},
                model_codec.config_section: {"description": str(face_file)},
            },
        }
        if not model:
            del engines[model_codec.name]
        for label, engine in engines.items():
            scenario = _scenario(name, label, path, (wlan_s, gsm_s), policy, max_backlog_ms, engine)
            out[label] = _gsm_figures(run_metrics(run_scenario(scenario)))
    return out


def _scenario(name, label, path, durations_s, policy, max_backlog_ms, engine):
    """The scenario of one engine: the clip as source, WLAN then GSM."""
    from uma.config.scenario import Scenario

    wlan_s, gsm_s = durations_s
    return Scenario.model_validate(
        {
            "name": f"face-rung-{name}-{label}",
            "seed": 1,
            "source": {"kind": "file", "path": path},
            "route": [
                {"technology": "WLAN", "duration_s": wlan_s},
                {"technology": "GSM", "duration_s": gsm_s},
            ],
            "engine": {"policy": policy}
            | ({} if max_backlog_ms is None else {"max_backlog_ms": max_backlog_ms})
            | engine,
            "receiver": {"playout_delay_ms": 800.0},
            "metrics": {"workers": 0},
        }
    )


def _gsm_figures(metrics: dict) -> dict:
    """What the bench reports of one run: the GSM stretch's and the rates."""
    gsm = metrics["by_technology"].get("GSM", {})
    return {
        "gsm_freeze_ratio": gsm.get("freeze_ratio"),
        "gsm_psnr_face_db": gsm.get("psnr_face_db"),
        "gsm_ssim_face": gsm.get("ssim_face"),
        "kbps_h264": metrics["kbps_h264"],
        "kbps_h264_face": metrics["kbps_h264_face"],
        "kbps_mbc": metrics["kbps_mbc"],
    }
