"""`uma report --video`: an MP4 of what the receiver displayed, beside the source.

The run is simulated again from its resolved `scenario.yaml` (the same seed gives the same run,
bit for bit: checked against the stored `frames.csv`), and each display instant's source frame
and shown picture are put side by side (the picture upscaled to the source size), with the
codec, the bit rate sent over the last second, the technology and FROZEN in a corner. Encoded
with libx264 through PyAV at the source's frame rate; written atomically.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uma.errors import RunError

__all__ = ["write_receiver_video"]


def _bgr(yuv: np.ndarray, width: int, height: int) -> np.ndarray:
    import cv2

    bgr = cv2.cvtColor(yuv, cv2.COLOR_YUV2BGR_I420)
    if bgr.shape[:2] != (height, width):
        bgr = cv2.resize(bgr, (width, height), interpolation=cv2.INTER_LINEAR)
    return bgr


def _label(image: np.ndarray, lines: list[str], *, colour=(255, 255, 255)) -> None:
    import cv2

    scale = max(0.35, image.shape[0] / 700.0)
    for i, text in enumerate(lines):
        y = int((i + 1) * 18 * scale / 0.4)
        cv2.putText(image, text, (6, y), cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), 3, cv2.LINE_AA)
        cv2.putText(image, text, (6, y), cv2.FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv2.LINE_AA)


def write_receiver_video(
    results_dir: str | Path, out_mp4: str | Path | None = None, *, rate_kbps: float = 2000.0
) -> Path:
    """Write `results_dir/receiver.mp4` (or `out_mp4`); returns its path."""
    import av

    from uma.atomic import atomic_open
    from uma.config import load_scenario
    from uma.report.results import read_run
    from uma.report.timeline import _rate_kbps
    from uma.sim import run_scenario

    run = read_run(results_dir)
    scenario = load_scenario(run.folder / "scenario.yaml")
    f = run.frames
    rate = _rate_kbps(f["capture_ms"] / 1000.0, np.nan_to_num(f["size_bits"]))
    out = Path(out_mp4) if out_mp4 is not None else run.folder / "receiver.mp4"
    shown_log: list[int] = []

    with atomic_open(out, "wb") as handle:
        container = av.open(handle, mode="w", format="mp4")
        stream = None

        def on_display(index: int, source: np.ndarray, shown: int, picture) -> None:
            nonlocal stream
            height, width = source.shape[0] * 2 // 3, source.shape[1]
            if stream is None:
                from fractions import Fraction

                stream = container.add_stream(
                    "libx264", rate=Fraction(scenario.source.fps).limit_denominator(1001)
                )
                stream.width, stream.height = 2 * width, height
                stream.pix_fmt = "yuv420p"
                stream.bit_rate = int(rate_kbps * 1000)
                stream.options = {"preset": "veryfast"}
            left = _bgr(source, width, height)
            right = np.zeros_like(left) if picture is None else _bgr(picture, width, height)
            frozen = bool(f["frozen"][index])
            shown_log.append(shown)
            codec = str(f["codec"][shown]) if shown >= 0 and "codec" in f else ""
            _label(left, ["source", f"{index / scenario.source.fps:6.2f} s"])
            _label(
                right,
                [
                    f"{codec or '-'} {rate[index]:.0f} kbit/s",
                    str(f["technology"][index]) if "technology" in f else "",
                    "FROZEN" if frozen else "",
                ],
                colour=(80, 80, 255) if frozen else (255, 255, 255),
            )
            frame = av.VideoFrame.from_ndarray(np.hstack([left, right]), format="bgr24")
            for packet in stream.encode(frame):
                container.mux(packet)

        try:
            run_scenario(scenario, on_display=on_display)
            if stream is not None:
                for packet in stream.encode(None):
                    container.mux(packet)
        finally:
            container.close()
        expected = f["shown_frame"].astype(int).tolist()
        if shown_log != expected:
            raise RunError(
                f"{run.folder}: the re-run displayed other frames than frames.csv records; "
                "the results come from another version of uma or were edited"
            )
    return out
