"""The model-aided refresh's schedule: which refresh picture is the receiver's reference when.

Units: frames (indices into the clip), seconds, bits, kbit/s.

Beside the parameter stream, a refresh stream codes every few frames of the clip (whole
pictures, e.g. H.264 at a low frame rate) with what the link has left. The receiver renders
every frame from the newest refresh picture it holds, at the frame's decoded pose, so the
schedule only says which picture that is. A unit leaves the sender at its frame's capture time
(`frame / clip_fps`), or when the unit before it has left, whichever is later, over a channel
of constant rate (the refresh's share of the link) plus a fixed latency; it serves from the
first frame captured at or after its last bit arrives. The parameters' own delay is the same
for both streams and not counted. A lost unit never serves; nor do the units after it up to
the next keyframe (they predict from a picture the receiver never decoded), so the reference
stays the last good one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uma.mbc.errors import SceneError

__all__ = ["RefreshUnit", "RefreshSchedule", "refresh_frames", "schedule_refresh"]


@dataclass(frozen=True)
class RefreshUnit:
    """One coded refresh picture: the frame it shows, its size, whether it decodes alone."""

    frame: int
    size_bits: int
    keyframe: bool = False
    lost: bool = False


@dataclass(frozen=True)
class RefreshSchedule:
    """`serving[f]`: the index (into the units) of the refresh picture the receiver renders
    frame f from, -1 for the picture it held before the first; `arrival_s[k]`: when unit k's
    last bit arrives (NaN if it never serves); `serves_from[k]`: the first frame it serves
    (-1 if never); `frames[k]`: unit k's own frame."""

    serving: np.ndarray
    arrival_s: np.ndarray
    serves_from: np.ndarray
    frames: np.ndarray

    def delay_frames(self) -> np.ndarray:
        """Per unit that serves, frames from its own frame to the first it serves."""
        used = self.serves_from >= 0
        return self.serves_from[used] - self.frames[used]


def refresh_frames(n_frames: int, clip_fps: float, refresh_fps: float) -> list[int]:
    """The frames (0 first) a refresh at `refresh_fps` codes out of `n_frames` at `clip_fps`:
    the nearest frame to each refresh instant, each at most once."""
    if int(n_frames) != n_frames or n_frames < 1:
        raise SceneError(f"refresh: n_frames: expected a positive integer, got {n_frames!r}")
    if not (math.isfinite(clip_fps) and clip_fps > 0):
        raise SceneError(f"refresh: clip_fps: expected positive, got {clip_fps!r}")
    if not (math.isfinite(refresh_fps) and 0 < refresh_fps <= clip_fps):
        raise SceneError(
            f"refresh: refresh_fps: expected in (0, clip_fps = {clip_fps}], got {refresh_fps!r}"
        )
    step = clip_fps / refresh_fps
    frames = sorted({int(round(k * step)) for k in range(int(n_frames / step) + 2)})
    return [f for f in frames if f < n_frames]


def schedule_refresh(
    units: list[RefreshUnit],
    n_frames: int,
    clip_fps: float,
    rate_kbps: float,
    *,
    latency_s: float = 0.0,
) -> RefreshSchedule:
    """The schedule of `units` (in sending order, frames increasing) over `n_frames` frames at
    `clip_fps` through a channel of `rate_kbps` (math.inf: instant) and `latency_s`; see the
    module. Units out of order, of negative size or on frames outside the clip are a
    `SceneError` naming the unit."""
    if not (clip_fps > 0 and math.isfinite(clip_fps)):
        raise SceneError(f"refresh: clip_fps: expected positive, got {clip_fps!r}")
    if not rate_kbps > 0:
        raise SceneError(f"refresh: rate_kbps: expected positive, got {rate_kbps!r}")
    if not (latency_s >= 0 and math.isfinite(latency_s)):
        raise SceneError(f"refresh: latency_s: expected >= 0, got {latency_s!r}")
    arrival = np.full(len(units), np.nan)
    serves_from = np.full(len(units), -1, dtype=np.int64)
    free_s, last_frame, broken = 0.0, -1, False
    for k, unit in enumerate(units):
        if not (0 <= unit.frame < n_frames) or unit.frame <= last_frame:
            raise SceneError(
                f"refresh unit {k}: expected a frame in ({last_frame}, {n_frames}), got "
                f"{unit.frame}"
            )
        if unit.size_bits < 0:
            raise SceneError(f"refresh unit {k}: expected size_bits >= 0, got {unit.size_bits}")
        last_frame = unit.frame
        start_s = max(unit.frame / clip_fps, free_s)
        free_s = start_s + unit.size_bits / (rate_kbps * 1000.0)
        if unit.keyframe:
            broken = False
        if unit.lost or broken:
            broken = True
            continue
        arrival[k] = free_s + latency_s
        # The first frame captured at or after the arrival (a hair of slack for rounding).
        first = int(math.ceil(arrival[k] * clip_fps - 1e-9))
        if first < n_frames:
            serves_from[k] = first
    serving = np.full(n_frames, -1, dtype=np.int64)
    for k in np.argsort(serves_from, kind="stable"):
        if serves_from[k] >= 0:
            serving[serves_from[k] :] = k  # FIFO: later units arrive later, so later wins
    frames = np.array([u.frame for u in units], dtype=np.int64)
    return RefreshSchedule(serving, arrival, serves_from, frames)
