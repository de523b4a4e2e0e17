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


class _Writer:
    """The side-by-side video of one re-run: each displayed instant as it comes."""

    def __init__(self, container, scenario, frames: dict, rate: np.ndarray, rate_kbps: float):
        self.container, self.scenario, self.f, self.rate = container, scenario, frames, rate
        self.rate_kbps = rate_kbps
        self.stream = None
        self.shown_log: list[int] = []

    def _open(self, width: int, height: int) -> None:
        from fractions import Fraction

        fps = Fraction(self.scenario.source.fps).limit_denominator(1001)
        self.stream = self.container.add_stream("libx264", rate=fps)
        self.stream.width, self.stream.height = 2 * width, height
        self.stream.pix_fmt = "yuv420p"
        self.stream.bit_rate = int(self.rate_kbps * 1000)
        self.stream.options = {"preset": "veryfast"}

    def on_display(self, index: int, source: np.ndarray, shown: int, picture) -> None:
        import av

        f = self.f
        height, width = source.shape[0] * 2 // 3, source.shape[1]
        if self.stream is None:
            self._open(width, height)
        left = _bgr(source, width, height)
        right = np.zeros_like(left) if picture is None else _bgr(picture, width, height)
        frozen = bool(f["frozen"][index])
        self.shown_log.append(shown)
        codec = str(f["codec"][shown]) if shown >= 0 and "codec" in f else ""
        _label(left, ["source", f"{index / self.scenario.source.fps:6.2f} s"])
        _label(
            right,
            [
                f"{codec or '-'} {self.rate[index]:.0f} kbit/s",
                str(f["technology"][index]) if "technology" in f else "",
                "FROZEN" if frozen else "",
            ],
            colour=(80, 80, 255) if frozen else (255, 255, 255),
        )
        frame = av.VideoFrame.from_ndarray(np.hstack([left, right]), format="bgr24")
        for packet in self.stream.encode(frame):
            self.container.mux(packet)

    def flush(self) -> None:
        if self.stream is not None:
            for packet in self.stream.encode(None):
                self.container.mux(packet)


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
    with atomic_open(out, "wb") as handle:
        container = av.open(handle, mode="w", format="mp4")
        writer = _Writer(container, scenario, f, rate, rate_kbps)
        try:
            run_scenario(scenario, on_display=writer.on_display)
            writer.flush()
        finally:
            container.close()
        if writer.shown_log != f["shown_frame"].astype(int).tolist():
            raise RunError(
                f"{run.folder}: the re-run displayed other frames than frames.csv records; "
                "the results come from another version of uma or were edited"
            )
    return out
