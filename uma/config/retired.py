"""Scenario keys that no longer mean anything, and why: refused with one line naming them.

A retired key is not merely unknown: a scenario that sets it was written for a mechanism that
is gone, and silently ignoring it would run something else than its author meant.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

__all__ = ["RETIRED", "find_retired"]

_ESTIMATOR_WHY = (
    "the old estimator's tuning; the rate controller (uma/control, docs/rate-control.md) "
    "has one set of defaults for every link"
)
RETIRED: dict[tuple[str, ...], str] = {
    **{
        ("engine", "estimator", key): _ESTIMATOR_WHY
        for key in (
            "queue_high_ms",
            "queue_low_ms",
            "decrease_factor",
            "increase_per_s",
            "loss_high",
            "window_s",
            "collapse_below",
            "increase_cap",
            "trend_window_s",
            "trend_high_ms_per_s",
        )
    },
    ("engine", "handover"): "the rate controller's technology priors replace it (always on)",
    ("engine", "pacer", "hold_after_ms"): (
        "the pacer no longer holds on silence; the rate controller lowers its target instead"
    ),
    ("engine", "pacer", "fit_frames"): "the rate controller's skip rule (Salsify's) replaces it",
    ("engine", "mbc", "probe"): (
        "the rate controller probes with padding whenever the stream is application-limited"
    ),
}


def find_retired(data: Any) -> tuple[tuple[str, ...], str] | None:
    """The first retired key `data` (a parsed scenario) sets, and why; None when none."""
    for path, why in RETIRED.items():
        node = data
        for key in path:
            if not isinstance(node, Mapping) or key not in node:
                break
            node = node[key]
        else:
            return path, why
    return None
