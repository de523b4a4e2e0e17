"""What the full-frame codecs (H.264, VP8, AV1) share: one PyAV encoder context per rung, one
decoder context, the encoded frame.

Units: rates in kbit/s, frame rates in frames/s, sizes in bits (`size_bits`) or bytes (`data`).
Frames are planar YUV 4:2:0 arrays of shape (H * 3 // 2, W), uint8, as everywhere in uma. Every
codec has this interface (`encode(frame, force_idr=...) -> EncodedFrame`,
`decode(data) -> array | None`), so a codec module only chooses the library and its options.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from dataclasses import asdict, dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from uma.errors import ConfigError, VideoError
from uma.video.planes import from_video_frame, to_video_frame

__all__ = [
    "EncodedFrame",
    "Retarget",
    "PyavEncoder",
    "PyavDecoder",
    "CodecSettings",
    "check_rung",
    "check_target",
    "check_keyint_vbv",
    "positive_number",
]


@dataclass(frozen=True)
class EncodedFrame:
    """One encoded picture (for H.264 an Annex B access unit), its presentation index and
    key-frame flag."""

    data: bytes
    pts: int
    is_keyframe: bool

    @property
    def size_bits(self) -> int:
        return 8 * len(self.data)


@dataclass(frozen=True)
class Retarget:
    """What `set_target` did: the rate the open encoder now aims at, or why it could not.

    Falsy when the encoder kept its old target (`reason` says why); the caller then has to open
    a new encoder, whose first frame is a key frame.
    """

    rate_kbps: float
    fps: float
    reason: str = ""

    def __bool__(self) -> bool:
        return not self.reason


def check_rung(where: str, width: int, height: int, fps: float, rate_kbps: float) -> None:
    """Refuse a size that is not even and positive, or a frame rate or rate that is not positive."""
    if width <= 0 or height <= 0 or width % 2 or height % 2:
        raise VideoError(f"{where}: expected an even positive size, got {width}x{height}")
    if not fps > 0 or not rate_kbps > 0:
        raise VideoError(f"{where}: expected positive fps and rate, got {fps}, {rate_kbps}")


def positive_number(value: Any) -> bool:
    """A finite number above 0 (not a bool)."""
    return (
        isinstance(value, int | float) and not isinstance(value, bool) and 0 < value < float("inf")
    )


def check_target(where: str, rate_kbps: float, fps: float | None = None) -> None:
    """Refuse a target rate, or a frame rate other than None, that is not a positive number."""
    if not positive_number(rate_kbps):
        raise VideoError(
            f"{where}: set_target: expected a positive rate in kbit/s, got {rate_kbps!r}"
        )
    if fps is not None and not positive_number(fps):
        raise VideoError(f"{where}: set_target: expected a positive fps, got {fps!r}")


def check_keyint_vbv(values: dict[str, Any], where: Callable[[str], str]) -> None:
    """`keyint_frames` a positive integer and `vbv_frames` at least 1, where present."""
    keyint = values.get("keyint_frames", 1)
    if not isinstance(keyint, int) or isinstance(keyint, bool) or keyint < 1:
        raise ConfigError(f"{where('keyint_frames')}: expected a positive integer, got {keyint!r}")
    vbv = values.get("vbv_frames", 1.0)
    if not isinstance(vbv, int | float) or isinstance(vbv, bool) or not vbv >= 1:
        raise ConfigError(f"{where('vbv_frames')}: expected a number of at least 1, got {vbv!r}")


class CodecSettings:
    """Base of a codec's frozen settings dataclass: what a ladder's `encoder:` section holds.

    A subclass names its `KEYS` (the dataclass fields, the keys a ladder may give) and
    `validate(values, where)`, which raises `ConfigError` naming `where(key)`; the values are
    checked on construction too. `kwargs()` are the keyword arguments of the codec's encoder.
    """

    NAME = "encoder"
    KEYS: tuple[str, ...] = ()

    @staticmethod
    def validate(values: dict[str, Any], where: Callable[[str], str]) -> None:
        raise NotImplementedError

    def __post_init__(self) -> None:
        self.validate(asdict(self), lambda key: f"{self.NAME} {key}")

    @classmethod
    def check(cls, values: dict[str, Any], where: Callable[[str], str]) -> None:
        """Raise `ConfigError` naming `where(key)` for the first bad value in `values`."""
        cls.validate(values, where)

    def kwargs(self) -> dict[str, Any]:
        return asdict(self)


class PyavEncoder:
    """A PyAV encoder context opened with `options`; one encoded frame out per frame in.

    `name` is the codec's label in messages (`VP8 encoder`), `library` the FFmpeg encoder name
    (`libvpx`). `options` are FFmpeg's AVOptions, the same names and values the ffmpeg command
    line takes (`-deadline realtime` is `{"deadline": "realtime"}`), kept in `self.options` so
    a benchmark can repeat the encode with the command line. `raw_muxer` is the FFmpeg muxer
    that writes its packets as they are, one after another (`uma bench codec --ffmpeg`).
    """

    raw_muxer = "ivf"
    # Whether `set_target` moves the open encoder's rate (opened with `max_rate_kbps`).
    retargets = False

    def __init__(
        self,
        name: str,
        library: str,
        width: int,
        height: int,
        fps: float,
        rate_kbps: float,
        options: dict[str, str],
    ) -> None:
        import av

        check_rung(name, width, height, fps, rate_kbps)
        self.name, self.library = name, library
        self.width, self.height, self.fps, self.rate_kbps = width, height, float(fps), rate_kbps
        self.frame_fps = self.fps  # the rate frames come in at; `set_target` may change it
        self.bit_rate = int(round(rate_kbps * 1000))
        self.options = dict(options)
        rate = Fraction(fps).limit_denominator(1001)
        context = av.CodecContext.create(library, "w")
        context.width = width
        context.height = height
        context.pix_fmt = "yuv420p"
        context.time_base = 1 / rate
        context.framerate = rate
        context.bit_rate = self.bit_rate
        context.options = self.options
        try:
            context.open()
        except av.FFmpegError as err:
            raise VideoError(f"{name}: {library} refused the settings ({err})") from None
        self._context = context
        self._picture_i = av.video.frame.PictureType.I
        self._pts = 0

    def set_target(self, rate_kbps: float, fps: float | None = None) -> Retarget:
        """Aim the open encoder at `rate_kbps` from the next frame on, without a key frame,
        with frames coming in at `fps` (None: as before).

        The base class cannot: FFmpeg's libvpx and SVT-AV1 wrappers (PyAV 18, libavcodec 62)
        read the rate once, when the encoder opens, and PyAV exposes no per-frame quantiser
        (docs/keyframe-free.md). It returns a falsy `Retarget` and keeps the old target;
        `H264Encoder` overrides it.
        """
        check_target(self.name, rate_kbps, fps)
        return Retarget(
            self.rate_kbps,
            self.frame_fps,
            f"{self.name}: {self.library} through FFmpeg does not change the rate of an open "
            "encoder; open a new one (its first frame is a key frame)",
        )

    def encode(self, frame: np.ndarray, *, force_idr: bool = False) -> EncodedFrame:
        """Encode one YUV 4:2:0 frame of the encoder's size; `force_idr` makes it a key frame."""
        import av

        expected = (self.height * 3 // 2, self.width)
        if frame.shape != expected or frame.dtype != np.uint8:
            raise VideoError(
                f"{self.name}: expected a {expected} uint8 frame, got {frame.shape} {frame.dtype}"
            )
        if self._context is None:
            raise VideoError(f"{self.name}: the encoder is closed")
        picture = to_video_frame(frame)
        picture.pts = self._pts
        if force_idr:
            picture.pict_type = self._picture_i
        try:
            packets = self._context.encode(picture)
        except av.FFmpegError as err:
            raise VideoError(
                f"{self.name}: {self.library} failed on frame {self._pts} ({err})"
            ) from None
        if len(packets) != 1:
            # the simulation's timing assumes no encoder delay (no lookahead, no frame dropping)
            raise VideoError(
                f"{self.name}: expected 1 packet for frame {self._pts}, got {len(packets)}"
            )
        self._pts += 1
        packet = packets[0]
        return EncodedFrame(
            data=bytes(packet), pts=picture.pts, is_keyframe=bool(packet.is_keyframe)
        )

    def close(self) -> None:
        """Flush the encoder (SVT-AV1 complains on stderr when torn down without it)."""
        context, self._context = getattr(self, "_context", None), None
        if context is not None:
            # closing must not raise (it runs from __del__); a low-delay encoder holds nothing
            with contextlib.suppress(Exception):
                context.encode(None)

    def __del__(self) -> None:
        self.close()


class PyavDecoder:
    """An FFmpeg decoder through PyAV; `decode` gives the picture of one packet, or None.

    One thread, so that every packet gives its picture at once. The decoder follows size changes
    in the stream (a new rung starts with a key frame). A damaged packet FFmpeg can still conceal
    gives a concealed picture and counts in `concealed_frames`; with `conceal=False` it raises
    `VideoError` instead. A packet FFmpeg rejects outright raises `VideoError`, never a PyAV
    error, and the decoder stays usable: the next key frame decodes.
    """

    UNIT = "packet"  # what one `decode` call takes, in messages

    def __init__(
        self, name: str, library: str, *, conceal: bool = True, options: dict | None = None
    ) -> None:
        import av

        self.name, self.library = name, library
        self.conceal = conceal
        self.concealed_frames = 0
        self._context = av.CodecContext.create(library, "r")
        self._context.thread_count = 1
        if options:
            self._context.options = dict(options)

    def decode(self, data: bytes) -> np.ndarray | None:
        """Decode one packet to a YUV 4:2:0 frame of the stream's current size.

        None when the packet yields no picture. Empty data raises `VideoError` (an empty packet
        would otherwise flush and end the decoder).
        """
        import av

        if not data:
            raise VideoError(f"{self.name}: empty {self.UNIT} (0 bytes)")
        try:
            frames = self._context.decode(av.Packet(data))
        except av.FFmpegError as err:
            raise VideoError(f"{self.name}: corrupt bitstream ({err})") from None
        if not frames:
            return None
        frame = frames[-1]
        if frame.is_corrupt:
            self.concealed_frames += 1
            if not self.conceal:
                raise VideoError(
                    f"{self.name}: corrupt bitstream (picture {self.concealed_frames} "
                    "needed error concealment)"
                )
        return from_video_frame(frame)
