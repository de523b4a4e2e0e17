"""H.264 encoding and decoding with libx264 and FFmpeg through PyAV.

Units: rates in kbit/s, sizes in bits, frame rates in frames/s. Frames are planar YUV 4:2:0
arrays of shape (H * 3 // 2, W), uint8.

Encoder settings for conversational video over a bottleneck: `ultrafast` + `zerolatency` (no
B-frames, no lookahead, one frame in gives one frame out), single-threaded so output is
deterministic, and VBV with maxrate = the target and a buffer of `vbv_frames` frame intervals, so
no frame exceeds what the link can drain in that time (ABR alone lets IDRs and scene cuts burst).
SPS/PPS are repeated in-band before every IDR (`repeat-headers`), so a receiver can join at any
IDR and a rung change (new size) needs no out-of-band setup.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from uma.errors import VideoError

__all__ = ["H264Encoder", "H264Decoder", "EncodedFrame"]


@dataclass(frozen=True)
class EncodedFrame:
    """One encoded picture (Annex B byte stream)."""

    data: bytes
    pts: int
    is_keyframe: bool

    @property
    def size_bits(self) -> int:
        return 8 * len(self.data)


class H264Encoder:
    """libx264 at a target rate; `encode` returns exactly one encoded frame per input frame."""

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
    ) -> None:
        import av

        if width <= 0 or height <= 0 or width % 2 or height % 2:
            raise VideoError(f"H.264 encoder: expected even positive size, got {width}x{height}")
        if fps <= 0 or rate_kbps <= 0:
            raise VideoError(
                f"H.264 encoder: expected positive fps and rate, got {fps}, {rate_kbps}"
            )
        self.width, self.height, self.fps, self.rate_kbps = width, height, fps, rate_kbps
        rate = Fraction(fps).limit_denominator(1001)
        bufsize_kbit = max(1.0, rate_kbps * vbv_frames / fps)
        context = av.CodecContext.create("libx264", "w")
        context.width = width
        context.height = height
        context.pix_fmt = "yuv420p"
        context.time_base = 1 / rate
        context.framerate = rate
        context.bit_rate = int(rate_kbps * 1000)
        params = (
            f"vbv-maxrate={rate_kbps:.3f}:vbv-bufsize={bufsize_kbit:.3f}:keyint={keyint_frames}:"
            "repeat-headers=1:annexb=1"
        )
        context.options = {"preset": preset, "tune": tune, "x264-params": params, "threads": "1"}
        try:
            context.open()
        except av.FFmpegError as err:
            raise VideoError(f"H.264 encoder: libx264 refused the settings ({err})") from None
        self._context = context
        self._pts = 0

    def encode(self, frame: np.ndarray, *, force_idr: bool = False) -> EncodedFrame:
        """Encode one YUV 4:2:0 frame of the encoder's size; `force_idr` makes it an IDR."""
        import av

        expected = (self.height * 3 // 2, self.width)
        if frame.shape != expected or frame.dtype != np.uint8:
            raise VideoError(f"H.264 encoder: expected a {expected} uint8 frame, got {frame.shape}")
        picture = av.VideoFrame.from_ndarray(frame, format="yuv420p")
        picture.pts = self._pts
        if force_idr:
            picture.pict_type = av.video.frame.PictureType.I
        packets = self._context.encode(picture)
        self._pts += 1
        if len(packets) != 1:
            # zerolatency promises no delay; anything else would break the simulation's timing
            raise VideoError(f"H.264 encoder: expected 1 packet per frame, got {len(packets)}")
        packet = packets[0]
        return EncodedFrame(
            data=bytes(packet), pts=picture.pts, is_keyframe=bool(packet.is_keyframe)
        )


class H264Decoder:
    """FFmpeg's H.264 decoder; `decode` gives the picture for one encoded frame, or None."""

    def __init__(self) -> None:
        import av

        self._context = av.CodecContext.create("h264", "r")

    def decode(self, data: bytes) -> np.ndarray | None:
        """Decode one Annex B access unit; None when it yields no picture.

        A corrupt bitstream raises `VideoError`, never a raw PyAV error.
        """
        import av

        try:
            frames = self._context.decode(av.Packet(data))
        except av.FFmpegError as err:
            raise VideoError(f"H.264 decoder: corrupt bitstream ({err})") from None
        if not frames:
            return None
        return frames[-1].to_ndarray(format="yuv420p")
