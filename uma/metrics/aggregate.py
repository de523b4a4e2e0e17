"""Aggregate one run's per-frame log into the numbers of `metrics.json`.

Units are in the key names: kbit/s, bits, ms, dB; ratios are fractions of 1. Percentiles use
numpy's default (linear) interpolation. PSNR and SSIM are means over every display instant,
frozen ones included (a frozen display is what the user sees); `ssim_db` = -10 log10(1 - SSIM)
of that mean, as Salsify reports it. Face-region scores (`psnr_face_db`, `ssim_face`) are means
over the display instants whose source frame has a face box (NaN cells are left out; null when
none has). `by_technology` gives, per access technology of the display instants, their freeze
ratio and face-region means.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable
from typing import Any

import numpy as np

from uma.codecs import REGISTRY, Role, metric_key, spec
from uma.metrics.delay import display_delays_ms
from uma.metrics.framelog import FrameLog

__all__ = ["aggregate", "by_technology", "ssim_to_db", "codec_bits"]


def _report_order(name: str) -> int:
    """`kbps_*` keys: full-frame codecs, then model codecs, then region codecs (the order of
    every earlier `metrics.json`), each in registry order."""
    roles = (Role.FULL_FRAME, Role.MODEL, Role.REGION)
    return roles.index(spec(name).role) * len(REGISTRY) + list(REGISTRY).index(name)


def codec_bits(log: FrameLog) -> dict[str, int]:
    """Bits sent per codec, in registry order: every codec the log names, and those the
    registry always reports (`CodecSpec.always_reported`) even when unused."""
    used = set(np.unique(log["codec"]).tolist()) - {""}
    unknown = used - set(REGISTRY)
    if unknown:
        raise ValueError(f"frame log: codecs {sorted(unknown)} are not in the registry")
    return {
        name: int(log["size_bits"][log["codec"] == name].sum())
        for name, codec in REGISTRY.items()
        if codec.always_reported or name in used
    }


def ssim_to_db(ssim: float) -> float:
    """-10 log10(1 - SSIM), capped at 100 dB for identical pictures."""
    if math.isnan(ssim):
        return float("nan")
    return 100.0 if ssim >= 1.0 - 1e-10 else -10.0 * math.log10(1.0 - ssim)


def _stat(values: np.ndarray, fn) -> float | None:
    values = values[np.isfinite(values)]
    return round(float(fn(values)), 4) if values.size else None


def by_technology(log: FrameLog, technologies: np.ndarray) -> dict[str, dict[str, Any]]:
    """Freeze ratio and face-region means of the display instants of each technology.

    `technologies[i]` is the access technology at display instant i; keys are sorted, and an
    empty technology (no coverage) is left out.
    """
    technologies = np.asarray(technologies).astype(str)
    out: dict[str, dict[str, Any]] = {}
    for technology in sorted(set(technologies.tolist()) - {""}):
        rows = technologies == technology
        out[technology] = {
            "freeze_ratio": round(float(log["frozen"][rows].mean()), 4),
            "psnr_face_db": _stat(log["psnr_face_db"][rows], np.mean),
            "ssim_face": _stat(log["ssim_face"][rows], np.mean),
        }
    return out


def aggregate(
    log: FrameLog,
    *,
    duration_s: float,
    capacity_bits: float,
    link: dict[str, int],
    event_kinds: Iterable[str],
) -> dict[str, Any]:
    """The aggregates of one run; `log["delay_ms"]` is filled in as a side effect."""
    delays = display_delays_ms(log["capture_ms"], log["display_ms"], log["shown_frame"])
    log["delay_ms"][:] = delays
    arrival = log["arrival_ms"] - log["capture_ms"]
    kinds = Counter(event_kinds)
    bits = codec_bits(log)
    ssim_values = log["ssim"][np.isfinite(log["ssim"])]
    # ssim_db from the unrounded mean: near 1, rounding SSIM to 4 decimals moves it by decibels.
    ssim_db = round(ssim_to_db(float(ssim_values.mean())), 4) if ssim_values.size else None
    p95 = lambda v: np.percentile(v, 95)  # noqa: E731
    return {
        "frames": int(log.frames),
        "duration_s": round(duration_s, 3),
        "frames_sent": int(log["sent"].sum()),
        "frames_decoded": int(log["decoded"].sum()),
        "idr_frames": int(log["keyframe"].sum()),
        "bits_sent": bits,
        **{
            f"kbps_{metric_key(name)}": round(bits[name] / duration_s / 1000.0, 3)
            for name in sorted(bits, key=_report_order)
        },
        "bits_delivered": int(link["bits_delivered"]),
        "capacity_mean_kbps": round(capacity_bits / duration_s / 1000.0, 3),
        "link_utilisation": round(link["bits_delivered"] / capacity_bits, 4)
        if capacity_bits
        else None,
        "packets": dict(link),
        "freeze_ratio": round(float(log["frozen"].mean()), 4) if log.frames else None,
        "psnr_db": _stat(log["psnr_db"], np.mean),
        "ssim": _stat(log["ssim"], np.mean),
        "ssim_db": ssim_db,
        "psnr_face_db": _stat(log["psnr_face_db"], np.mean),
        "ssim_face": _stat(log["ssim_face"], np.mean),
        "delay_median_ms": _stat(delays, np.median),
        "delay_p95_ms": _stat(delays, p95),
        "arrival_delay_median_ms": _stat(arrival, np.median),
        "arrival_delay_p95_ms": _stat(arrival, p95),
        "switches": kinds.get("rung_switch", 0),
        "handovers": kinds.get("handover", 0),
        "keyframe_requests": kinds.get("keyframe_request", 0),
    }
