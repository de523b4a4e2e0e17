"""H.264 encoding and decoding with libx264 and FFmpeg through PyAV.

Units: rates in kbit/s, sizes in bits (`size_bits`) or bytes (`data`), frame rates in frames/s,
the VBV buffer in frame intervals (`vbv_frames`). Frames are planar YUV 4:2:0 arrays of shape
(H * 3 // 2, W), uint8; the bitstream is Annex B (start codes), one access unit per frame.

Settings for conversational video over a bottleneck, and why:
- `tune=zerolatency`: no B-frames, no lookahead, no frame threads, so one frame in gives one
  frame out (checked on every call; the simulation's timing depends on it). A tune without
  `zerolatency` is refused.
- One thread: deterministic output for a given input and settings, and the cores stay free
  for the simulation and the quality metrics.
- Rate control: ABR at the target with VBV `maxrate` = the target and `bufsize` = `vbv_frames`
  frame intervals (default 4, i.e. 160 ms at 25 fps, 800 ms at 5 fps). A link draining at
  exactly the target rate then never queues more than the VBV buffer of this stream, IDRs
  included (measured peak 0.78-0.95 of it over every ladder rung on akiyo, carphone, foreman
  and the pattern); ABR alone lets an IDR reach 2-12 frame budgets and a one-second window
  +19 to +190 %. With maxrate = target libx264 undershoots, never overshoots, the long-run
  target; measured steady-state error over the ladder rungs on the three clips, by buffer
  size: 1 frame -21 to -44 %, 2 frames -11 to -28 %, 4 frames -3 to -15 % (worst on the still
  akiyo at 16-24 kbit/s, 5 frames/s), 6 frames -2 to -12 % but a one-second window then
  reaches +64 % at 5 frames/s. A single-frame VBV (x264's classic low-latency advice, paired
  with intra refresh) wastes a quarter or more of the link here, so 4 frames is the default.
- The VBV is given twice, in `x264-params` and as FFmpeg's `maxrate`/`bufsize`, with the same
  values (the output is byte for byte the same). FFmpeg's wrapper compares its context's
  `maxrate`/`bufsize` with x264's before every frame and reconfigures x264 when they differ: with
  the VBV only in `x264-params` it switches the VBV off in its copy of the parameters on the
  first frame, after which x264 ignores every change of `bit_rate`. With both, `set_target`
  reaches `x264_encoder_reconfig` and the open encoder follows a new rate without an IDR.
- `repeat-headers`: SPS and PPS in front of every IDR, so a decoder can start at any IDR and a
  rung change (a new encoder at a new size) needs nothing out of band. `forced-idr`: a forced
  key frame is a real IDR (NAL type 5), not a recovery-point I-frame.
"""

from __future__ import annotations

import math

from uma.errors import VideoError
from uma.video.pyav_codec import (
    EncodedFrame,
    PyavDecoder,
    PyavEncoder,
    Retarget,
    check_rung,
    check_target,
    positive_number,
)

__all__ = ["H264Encoder", "H264Decoder", "EncodedFrame", "nal_unit_types", "NAL_IDR", "PRESETS"]

NAL_IDR = 5  # nal_unit_type of an IDR slice (H.264 table 7-1); 1 is a non-IDR slice, 7 SPS, 8 PPS

PRESETS = (
    "ultrafast",
    "superfast",
    "veryfast",
    "faster",
    "fast",
    "medium",
    "slow",
    "slower",
    "veryslow",
    "placebo",
)


def nal_unit_types(data: bytes) -> list[int]:
    """The nal_unit_type of each NAL unit in an Annex B byte stream, in order."""
    types = []
    start = data.find(b"\x00\x00\x01")
    while 0 <= start < len(data) - 3:
        types.append(data[start + 3] & 0x1F)
        start = data.find(b"\x00\x00\x01", start + 3)
    return types


class H264Encoder(PyavEncoder):
    """libx264 at a target rate; `encode` returns exactly one encoded frame per input frame.

    One encoder serves one size. `set_target` changes its rate, and the frame rate frames come
    in at, without an IDR, as long as it asks x264 for at most `max_rate_kbps` (default: the
    opening rate), the VBV cap it is opened with; a change of size makes a new encoder, whose
    first frame is an IDR. `keyint_frames` is
    the longest run between IDRs; conversational senders mostly send IDRs on request
    (`force_idr`).
    """

    raw_muxer = "h264"  # an Annex B stream (`annexb=1`), for the ffmpeg command line
    retargets = True

    def __init__(
        self,
        width: int,
        height: int,
        fps: float,
        rate_kbps: float,
        *,
        preset: str = "ultrafast",
        tune: str = "zerolatency",
        keyint_frames: int = 250,
        vbv_frames: float = 4.0,
        max_rate_kbps: float | None = None,
    ) -> None:
        where = "H.264 encoder"
        check_rung(where, width, height, fps, rate_kbps)
        ceiling_kbps = rate_kbps if max_rate_kbps is None else max_rate_kbps
        if not positive_number(ceiling_kbps) or not ceiling_kbps >= rate_kbps:
            raise VideoError(
                f"{where}: max_rate_kbps: expected at least the rate {rate_kbps}, "
                f"got {max_rate_kbps!r}"
            )
        if preset not in PRESETS:
            raise VideoError(
                f"{where}: preset: expected one of {', '.join(PRESETS)}, got {preset!r}"
            )
        if "zerolatency" not in tune.split(","):
            raise VideoError(
                f"{where}: tune: expected 'zerolatency' among the tunes (one frame out per frame "
                f"in), got {tune!r}"
            )
        if int(keyint_frames) != keyint_frames or keyint_frames < 1:
            raise VideoError(
                f"{where}: keyint_frames: expected a positive integer, got {keyint_frames!r}"
            )
        if not vbv_frames >= 1:
            raise VideoError(f"{where}: vbv_frames: expected at least 1, got {vbv_frames!r}")
        self.preset, self.tune = preset, tune
        self.keyint_frames, self.vbv_frames = int(keyint_frames), float(vbv_frames)
        # x264 reads whole kbit (a decimal is an "Error parsing option" and truncated): pass whole
        # kbit, rounded down so the cap never exceeds the target, and keep what x264 uses.
        self.vbv_maxrate_kbit = max(1, math.floor(ceiling_kbps))
        self.vbv_bufsize_kbit = max(1, math.floor(rate_kbps * vbv_frames / fps))
        self.x264_params = params = (
            f"vbv-maxrate={self.vbv_maxrate_kbit}:vbv-bufsize={self.vbv_bufsize_kbit}:"
            f"keyint={self.keyint_frames}:repeat-headers=1:annexb=1"
        )
        options = {
            "preset": preset,
            "tune": tune,
            "x264-params": params,
            "forced-idr": "1",
            "threads": "1",
            "maxrate": str(1000 * self.vbv_maxrate_kbit),
            "bufsize": str(1000 * self.vbv_bufsize_kbit),
        }
        # opened at the ceiling so x264 starts in CBR (maxrate = rate), the mode whose rate it
        # can reconfigure; then aimed at the rate before the first frame
        super().__init__(where, "libx264", width, height, fps, ceiling_kbps, options)
        if ceiling_kbps != rate_kbps:
            self.set_target(rate_kbps)

    def set_target(self, rate_kbps: float, fps: float | None = None) -> Retarget:
        """Aim the open encoder at `rate_kbps` from the next frame on, without an IDR, with
        frames coming in at `fps` (None: the rate they come in at now; at first `self.fps`).

        x264 stays in CBR: its VBV cap follows the new rate, its VBV buffer keeps the size in
        bits it was opened with (`vbv_bufsize_kbit`), so below the opening rate it holds more
        frame intervals of the new rate. With `tune=zerolatency` x264 ignores timestamps and
        gives each frame (its rate) / (the frame rate it was opened with): frames at another
        `fps` get the rate `rate_kbps * self.fps / fps` asked of x264. A rate that asks x264
        for more than `max_rate_kbps` (the `maxrate` FFmpeg opened it with, which PyAV cannot
        change) is refused: the result is falsy, the old target stays, and a new encoder is
        needed. x264 takes whole kbit/s (rounded down).
        """
        check_target(self.name, rate_kbps, fps)
        if self._context is None:
            raise VideoError(f"{self.name}: the encoder is closed")
        fps = self.frame_fps if fps is None else float(fps)
        kbit = max(1, math.floor(rate_kbps * self.fps / fps))
        if kbit > self.vbv_maxrate_kbit:
            return Retarget(
                self.rate_kbps,
                self.frame_fps,
                f"{self.name}: {rate_kbps} kbit/s at {fps:g} frames/s asks x264 for {kbit} "
                f"kbit/s at {self.fps:g}, above the {self.vbv_maxrate_kbit} kbit/s the encoder "
                "was opened with (max_rate_kbps); open a new one",
            )
        self._context.bit_rate = self.bit_rate = 1000 * kbit
        self.rate_kbps, self.frame_fps = rate_kbps, fps
        return Retarget(rate_kbps, fps)


class H264Decoder(PyavDecoder):
    """FFmpeg's H.264 decoder; `decode` gives the picture of one access unit, or None.

    The decoder follows size changes in the stream (a new rung starts with an IDR carrying its
    SPS). A damaged access unit that FFmpeg can still conceal (missing slices, flipped bits)
    gives a concealed picture and counts in `concealed_frames`; with `conceal=False` it raises
    `VideoError` instead. A stream FFmpeg rejects outright raises `VideoError`, never a PyAV
    error, and the decoder stays usable: the next IDR decodes.
    """

    UNIT = "access unit"

    def __init__(self, *, conceal: bool = True) -> None:
        super().__init__("H.264 decoder", "h264", conceal=conceal)
