"""VP8 encoding with libvpx and decoding with FFmpeg's VP8 decoder, through PyAV.

Units: rates in kbit/s, frame rates in frames/s, the rate-control buffer in frame intervals
(`vbv_frames`, as for H.264). Frames are planar YUV 4:2:0 arrays (H * 3 // 2, W), uint8; a
packet is one VP8 frame (no container).

Settings are WebRTC's real-time VP8 configuration (`LibvpxVp8Encoder`), with two changes the
simulation needs (see docs/codecs.md for the measurements behind them):
- `deadline=realtime`, `cpu-used` -6 from CIF up and -4 below (WebRTC's rule on x86: more effort
  on small pictures), `lag-in-frames=0` (no lookahead: one frame out per frame in, checked on
  every call), `error-resilient=default` (no probability context carried across frames, so a
  lost frame does not damage the entropy decoding of later ones), one thread.
- CBR (`minrate` = `maxrate` = the target), under- and overshoot 100 % and 15 %, quantiser up
  to 56, static threshold 1, and the key-frame cap WebRTC derives from its buffer
  (`max-intra-rate`, at least 300 % of a frame's budget).
- Quantiser from 0, not WebRTC's 2: on a still scene at a high rung (akiyo, CIF, 1200 kbit/s)
  the floor of 2 leaves a third of the rate unspent; from 0 libvpx reaches the target, as
  libx264 does, so the codecs are compared at the rates the ladder names.
- The buffer is `vbv_frames` frame intervals (default 4, as for H.264) instead of WebRTC's
  1000 ms, so both codecs promise the same bounded queue on a link at the target rate. It
  starts half full, as WebRTC's does (500 of 1000 ms).
- Frame dropping off (WebRTC drops at 30 % buffer underflow): the engine decides which frames
  to skip, and one packet per frame keeps the simulation's timing.
- Key frames only on request (`force_idr`) or every `keyint_frames` (default 250, as the H.264
  ladder; WebRTC's is 3000).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from uma.errors import ConfigError, VideoError
from uma.video.pyav_codec import CodecSettings, PyavDecoder, PyavEncoder, check_keyint_vbv

__all__ = ["VP8Encoder", "VP8Decoder", "VP8Settings", "webrtc_cpu_used"]


def webrtc_cpu_used(width: int, height: int) -> int:
    """WebRTC's libvpx speed for VP8 on x86: -6, or -4 below CIF's area (more effort there)."""
    return -4 if width * height < 352 * 288 else -6


def _check(values: dict[str, Any], where: Callable[[str], str]) -> None:
    cpu_used = values.get("cpu_used")
    if cpu_used is not None and (
        not isinstance(cpu_used, int) or isinstance(cpu_used, bool) or not -16 <= cpu_used <= 16
    ):
        raise ConfigError(
            f"{where('cpu_used')}: expected an integer from -16 to 16 (or null for WebRTC's "
            f"choice by size), got {cpu_used!r}"
        )
    check_keyint_vbv(values, where)


@dataclass(frozen=True)
class VP8Settings(CodecSettings):
    """libvpx settings shared by every rung of a VP8 ladder (`encoder:` in codecs/vp8.yaml)."""

    cpu_used: int | None = None
    keyint_frames: int = 250
    vbv_frames: float = 4.0

    NAME = "VP8 encoder"
    KEYS = ("cpu_used", "keyint_frames", "vbv_frames")
    validate = staticmethod(_check)


class VP8Encoder(PyavEncoder):
    """libvpx VP8 at a target rate; `encode` returns exactly one encoded frame per input frame.

    One encoder serves one rung (size, frame rate, rate): a rung change makes a new encoder,
    whose first frame is a key frame. `cpu_used` None takes WebRTC's choice for the size.
    """

    def __init__(
        self,
        width: int,
        height: int,
        fps: float,
        rate_kbps: float,
        *,
        cpu_used: int | None = None,
        keyint_frames: int = 250,
        vbv_frames: float = 4.0,
    ) -> None:
        try:
            _check(
                {"cpu_used": cpu_used, "keyint_frames": keyint_frames, "vbv_frames": vbv_frames},
                lambda key: f"VP8 encoder: {key}",
            )
        except ConfigError as err:
            raise VideoError(str(err)) from None
        self.cpu_used = webrtc_cpu_used(width, height) if cpu_used is None else cpu_used
        self.keyint_frames, self.vbv_frames = int(keyint_frames), float(vbv_frames)
        bit_rate = int(round(rate_kbps * 1000))
        buffer_bits = int(round(bit_rate * self.vbv_frames / fps)) if fps > 0 else 0
        # WebRTC's MaxIntraTarget: half the optimal buffer level (FFmpeg puts it at 5/6 of the
        # buffer) in percent of a frame's budget, at least 300 %: 1000 ms * 5/6 * 0.5 * fps / 10
        # per second of buffer, i.e. vbv_frames * 125 / 3
        self.max_intra_pct = max(300, int(self.vbv_frames * 125 / 3))
        options = {
            "deadline": "realtime",
            "cpu-used": str(self.cpu_used),
            "lag-in-frames": "0",
            "auto-alt-ref": "0",
            "error-resilient": "default",
            "minrate": str(bit_rate),
            "maxrate": str(bit_rate),
            "bufsize": str(buffer_bits),
            "rc_init_occupancy": str(buffer_bits // 2),
            "undershoot-pct": "100",
            "overshoot-pct": "15",
            "max-intra-rate": str(self.max_intra_pct),
            "static-thresh": "1",
            "drop-threshold": "0",
            "qmin": "0",
            "qmax": "56",
            "g": str(self.keyint_frames),
            "threads": "1",
        }
        super().__init__("VP8 encoder", "libvpx", width, height, fps, rate_kbps, options)


class VP8Decoder(PyavDecoder):
    """FFmpeg's native VP8 decoder; `decode` gives the picture of one packet, or None."""

    def __init__(self, *, conceal: bool = True) -> None:
        super().__init__("VP8 decoder", "vp8", conceal=conceal)
