"""Per-frame accounting of one run: one row per source frame, filled in as the frame travels.

Units live in the column names: times in ms from the start of the run, rates in kbit/s, sizes in
bits, PSNR in dB, SSIM unitless. Missing values are NaN (floats) or -1 (integers).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.codecs import REGISTRY

__all__ = ["FrameLog", "COLUMNS"]

# Codec columns hold any registered name whole (a fixed width shorter than one would cut it).
CODEC_DTYPE = f"U{max(len(name) for name in REGISTRY)}"

# name -> (dtype, missing value); the order is the CSV's.
COLUMNS: dict[str, tuple[str, float]] = {
    "frame": ("i8", -1),
    "capture_ms": ("f8", np.nan),
    "display_ms": ("f8", np.nan),
    "technology": ("U8", ""),
    "capacity_kbps": ("f8", np.nan),
    "estimate_kbps": ("f8", np.nan),
    # Bytes waiting when the engine decided on the frame: in the bottleneck's queue, and in
    # the engine's own (its pacer; 0 without one).
    "queue_bytes": ("i8", 0),
    "engine_queue_bytes": ("i8", 0),
    "codec": (CODEC_DTYPE, ""),
    "rung": ("i8", -1),
    "width": ("i8", -1),
    "height": ("i8", -1),
    "scheduled": ("i8", 0),
    "sent": ("i8", 0),
    "keyframe": ("i8", 0),
    "size_bits": ("i8", 0),
    "arrival_ms": ("f8", np.nan),
    "decoded": ("i8", 0),
    "shown_frame": ("i8", -1),
    "shown_codec": (CODEC_DTYPE, ""),
    "frozen": ("i8", 0),
    "delay_ms": ("f8", np.nan),
    "psnr_db": ("f8", np.nan),
    "ssim": ("f8", np.nan),
    "psnr_face_db": ("f8", np.nan),
    "ssim_face": ("f8", np.nan),
}


@dataclass
class FrameLog:
    """Column arrays of length `frames`; processes write their own columns by frame index."""

    frames: int

    def __post_init__(self) -> None:
        self.columns: dict[str, np.ndarray] = {}
        for name, (dtype, missing) in COLUMNS.items():
            self.columns[name] = np.full(self.frames, missing, dtype=dtype)
        self.columns["frame"][:] = np.arange(self.frames)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def to_csv(self) -> str:
        """The log as CSV text: a header of unit-carrying names, one row per frame."""
        lines = [",".join(COLUMNS)]
        formatted = [_format_column(self.columns[name]) for name in COLUMNS]
        for row in zip(*formatted, strict=True):
            lines.append(",".join(row))
        return "\n".join(lines) + "\n"


def _format_column(values: np.ndarray) -> list[str]:
    if values.dtype.kind == "f":
        return ["" if np.isnan(v) else f"{v:.3f}" for v in values.tolist()]
    return [str(v) for v in values.tolist()]
