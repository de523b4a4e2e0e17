"""AV1 encoding with SVT-AV1 and decoding with dav1d, through PyAV.

Units: rates in kbit/s, frame rates in frames/s, the rate-control buffer in frame intervals
(`vbv_frames`, as for H.264). Frames are planar YUV 4:2:0 arrays (H * 3 // 2, W), uint8; a
packet is one temporal unit of OBUs (low-overhead bitstream format, no container).

Settings for conversational video, and why (measurements in docs/codecs.md):
- `rtc=1`, SVT-AV1's real-time mode, at `preset` 12, its fastest there (13 is mapped to 12): a
  CIF frame costs a few ms on one thread, within the simulation's budget; preset 10 gains
  about 1 dB PSNR for 1.5 to 2 times the time.
- `pred-struct=1` (low delay: no B-frames, no reordering) and no lookahead, so one frame in
  gives one packet out (checked on every call); `lp=1`, one thread, for deterministic output
  and free cores for the simulation.
- `rc=2`, CBR at the target, with a buffer (`buf-sz`) of `vbv_frames` frame intervals (default
  4, as for H.264), starting and aimed at half full (`buf-initial-sz`, `buf-optimal-sz`).
- Key frames only on request (`force_idr`) or every `keyint_frames` (default 250, as for the
  H.264 ladder). Every key frame carries the sequence header, so a decoder can start there.
- dav1d decodes on one thread, so every packet gives its picture at once.
SVT-AV1 logs to stderr; unless the user sets `SVT_LOG`, only its errors are shown.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from uma.errors import ConfigError, VideoError
from uma.video.pyav_codec import CodecSettings, PyavDecoder, PyavEncoder, check_keyint_vbv

__all__ = ["AV1Encoder", "AV1Decoder", "AV1Settings", "AV1_PRESETS"]

AV1_PRESETS = range(0, 13)  # SVT-AV1 presets, slowest to fastest in real-time mode (rtc=1)


def _whole(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _check(values: dict[str, Any], where: Callable[[str], str]) -> None:
    preset = values.get("preset", AV1_PRESETS[-1])
    if not _whole(preset) or preset not in AV1_PRESETS:
        raise ConfigError(
            f"{where('preset')}: expected an SVT-AV1 preset from {AV1_PRESETS[0]} to "
            f"{AV1_PRESETS[-1]}, got {preset!r}"
        )
    check_keyint_vbv(values, where)


@dataclass(frozen=True)
class AV1Settings(CodecSettings):
    """SVT-AV1 settings shared by every rung of an AV1 ladder (`encoder:` in codecs/av1.yaml)."""

    preset: int = AV1_PRESETS[-1]
    keyint_frames: int = 250
    vbv_frames: float = 4.0

    NAME = "AV1 encoder"
    KEYS = ("preset", "keyint_frames", "vbv_frames")
    validate = staticmethod(_check)


class AV1Encoder(PyavEncoder):
    """SVT-AV1 at a target rate; `encode` returns exactly one encoded frame per input frame.

    One encoder serves one rung (size, frame rate, rate): a rung change makes a new encoder,
    whose first frame is a key frame. `svtav1_params` holds what SVT-AV1 is given beyond
    FFmpeg's own options (the ffmpeg command line's `-svtav1-params`).
    """

    def __init__(
        self,
        width: int,
        height: int,
        fps: float,
        rate_kbps: float,
        *,
        preset: int = AV1_PRESETS[-1],
        keyint_frames: int = 250,
        vbv_frames: float = 4.0,
    ) -> None:
        try:
            _check(
                {"preset": preset, "keyint_frames": keyint_frames, "vbv_frames": vbv_frames},
                lambda key: f"AV1 encoder: {key}",
            )
        except ConfigError as err:
            raise VideoError(str(err)) from None
        self.preset, self.keyint_frames, self.vbv_frames = preset, keyint_frames, float(vbv_frames)
        buffer_ms = int(round(1000.0 * self.vbv_frames / fps)) if fps > 0 else 1
        self.svtav1_params = (
            f"rtc=1:pred-struct=1:rc=2:lp=1:buf-sz={buffer_ms}:"
            f"buf-initial-sz={buffer_ms // 2}:buf-optimal-sz={buffer_ms // 2}"
        )
        # no `maxrate`: SVT-AV1 1.4 (Debian 12's) refuses a cap equal to the target
        options = {
            "preset": str(preset),
            "svtav1-params": self.svtav1_params,
            "g": str(keyint_frames),
        }
        os.environ.setdefault("SVT_LOG", "1")  # errors only: SVT-AV1 prints its settings
        super().__init__("AV1 encoder", "libsvtav1", width, height, fps, rate_kbps, options)


class AV1Decoder(PyavDecoder):
    """dav1d; `decode` gives the picture of one temporal unit, or None."""

    def __init__(self, *, conceal: bool = True) -> None:
        super().__init__(
            "AV1 decoder", "libdav1d", conceal=conceal, options={"max_frame_delay": "1"}
        )
