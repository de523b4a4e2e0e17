"""`uma bench codec --ffmpeg`: each rung coded again by the ffmpeg command line, same settings.

Units: kbit/s after the first second, percent. The frames a rung codes (resized and decimated
as `uma.bench.codec.measure_rung` does) go to `ffmpeg` as raw YUV 4:2:0 on stdin, with the
encoder's own options (`-deadline realtime -cpu-used -6 ...` for VP8, `-preset 12
-svtav1-params ...` for AV1, `-preset ... -x264-params ...` for H.264); the packet sizes are
read back from the IVF (VP8, AV1) or Annex B (H.264) output. The ffmpeg binary links its own
codec libraries, whose versions may differ from PyAV's: `ffmpeg_version` says which ffmpeg.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import struct
import subprocess
import tempfile
from collections.abc import Iterable
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from uma.errors import RunError

__all__ = ["ffmpeg_version", "encoder_arguments", "compare_rung"]


def ffmpeg_version() -> str:
    """The first line of `ffmpeg -version`; `RunError` when no ffmpeg is on the PATH."""
    if shutil.which("ffmpeg") is None:
        raise RunError("--ffmpeg: expected an ffmpeg command on the PATH, found none")
    out = subprocess.run(["ffmpeg", "-version"], capture_output=True, text=True, check=True)
    return out.stdout.splitlines()[0]


def encoder_arguments(encoder) -> tuple[list[str], str]:
    """(ffmpeg output arguments, muxer) that repeat `encoder`'s settings: its FFmpeg library,
    rate and AVOptions (`PyavEncoder.options`, the command line's names), written by the
    muxer its class names (`raw_muxer`: IVF frames, or an Annex B stream)."""
    args = ["-c:v", encoder.library, "-b:v", str(encoder.bit_rate)]
    for key, value in encoder.options.items():
        args += [f"-{key}", value]
    return args, encoder.raw_muxer


def _ivf_sizes(data: bytes) -> list[int]:
    header = struct.unpack_from("<H", data, 6)[0]  # 32 bytes, then 12 before each frame
    sizes, at = [], header
    while at + 12 <= len(data):
        size = struct.unpack_from("<I", data, at)[0]
        sizes.append(size)
        at += 12 + size
    return sizes


def _demuxed_sizes(path: Path, muxer: str) -> list[int]:
    import av

    with av.open(str(path), format=muxer) as container:
        return [packet.size for packet in container.demux(video=0) if packet.size]


def _steady_kbps(sizes_bytes: list[int], fps: float) -> float:
    skip = max(1, int(round(fps)))
    return 8 * sum(sizes_bytes[skip:]) / ((len(sizes_bytes) - skip) / fps) / 1000.0


def compare_rung(codec: str, rung, settings, frames: Iterable[np.ndarray]) -> dict[str, Any]:
    """PyAV's and the command line's rate at one rung on the same frames (a clip at 25 fps,
    read once, in order: each frame goes to both encoders as it comes, none is held)."""
    from uma.bench.codec import CLIP_FPS, codec_classes
    from uma.video import resize_yuv420

    encoder_class, _ = codec_classes(codec)
    step = max(1, int(round(CLIP_FPS / rung.fps)))
    encoder = encoder_class(rung.width, rung.height, rung.fps, rung.rate_kbps, **settings.kwargs())
    rate = Fraction(rung.fps).limit_denominator(1001)
    args, muxer = encoder_arguments(encoder)
    pyav = []
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / f"out.{muxer}"
        command = ["ffmpeg", "-hide_banner", "-loglevel", "error", "-f", "rawvideo"]
        command += ["-pix_fmt", "yuv420p", "-s", f"{rung.width}x{rung.height}"]
        command += ["-framerate", f"{rate.numerator}/{rate.denominator}", "-i", "-"]
        command += [*args, "-f", muxer, "-y", str(out)]
        errors = Path(folder) / "stderr.txt"
        with open(errors, "wb") as stderr:
            process = subprocess.Popen(
                command,
                stdin=subprocess.PIPE,
                stdout=subprocess.DEVNULL,
                stderr=stderr,
                env={**os.environ, "SVT_LOG": os.environ.get("SVT_LOG", "1")},
            )
            try:
                for index, frame in enumerate(frames):
                    if index % step:
                        continue
                    small = np.ascontiguousarray(resize_yuv420(frame, rung.width, rung.height))
                    pyav.append(len(encoder.encode(small).data))
                    process.stdin.write(small.tobytes())
            except BrokenPipeError:
                pass  # ffmpeg stopped early: its message is read below
            finally:
                with contextlib.suppress(BrokenPipeError):
                    process.stdin.close()
                returncode = process.wait()
        if returncode != 0:
            message = errors.read_bytes().decode(errors="replace").strip().splitlines()
            raise RunError(f"ffmpeg failed on {codec} {rung.label}: {message[-1:]}")
        cli = _ivf_sizes(out.read_bytes()) if muxer == "ivf" else _demuxed_sizes(out, muxer)
    if len(cli) != len(pyav):
        raise RunError(f"ffmpeg gave {len(cli)} packets for {len(pyav)} frames ({codec})")
    pyav_kbps, cli_kbps = _steady_kbps(pyav, rung.fps), _steady_kbps(cli, rung.fps)
    return {
        "target_kbps": rung.rate_kbps,
        "kbps": round(pyav_kbps, 2),
        "ffmpeg_kbps": round(cli_kbps, 2),
        "diff_pct": round(100.0 * (pyav_kbps / cli_kbps - 1.0), 2),
        "same_sizes": pyav == cli,
    }


def compare_codecs(
    codecs: tuple[str, ...], videos: list, *, frames: int = 300, progress=None
) -> dict[str, Any]:
    """`{"version", "codecs": {codec: {clip: [compare_rung rows]}}}` over every ladder rung."""
    from uma.bench.codec_clip import open_clip
    from uma.video import default_ladder_path, load_ladder

    result: dict[str, Any] = {"version": ffmpeg_version(), "codecs": {}}
    clips = [open_clip(video, frames, faces=False) for video in videos]
    for codec in codecs:
        ladder = load_ladder(default_ladder_path(codec))
        result["codecs"][codec] = {}
        for clip in clips:
            rows = []
            for rung in ladder.rungs:
                if progress is not None:
                    progress(f"ffmpeg {codec} {clip.name} {rung.label}")
                rows.append(compare_rung(codec, rung, ladder.encoder, clip.frames()))
            result["codecs"][codec][clip.name] = rows
    return result


def format_ffmpeg_table(result: dict[str, Any]) -> str:
    lines = [f"against the command line ({result['version']}), same settings, same frames"]
    for codec, clips in result["codecs"].items():
        for clip, rows in clips.items():
            lines.append(f"  {codec} on {clip}: target  PyAV  ffmpeg  diff %  same sizes")
            for row in rows:
                lines.append(
                    f"  {'':<12}{row['target_kbps']:>8g}{row['kbps']:>8.1f}{row['ffmpeg_kbps']:>8.1f}"
                    f"{row['diff_pct']:>8.2f}  {'yes' if row['same_sizes'] else 'no'}"
                )
    return "\n".join(lines)
