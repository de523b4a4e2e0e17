"""`uma bench mbc --picture FILE`: source | MBC | MBC + refresh | H.264 | AV1, side by side.

Units: pixels. One row per clip, at one instant (the same frame of each display), each panel
at the clip's size scaled to a common height, labelled with the display and its payload rate,
so a reader sees seams, ghosts and colours where the numbers only average them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["PANELS", "side_by_side", "save_side_by_side"]

PANELS = ("source", "quantised", "mbc_refresh_lowest", "h264_lowest", "av1_lowest")
_LABELS = {
    "source": "source",
    "quantised": "MBC",
    "mbc_refresh_lowest": "MBC+refresh",
    "h264_lowest": "H.264 alone",
    "av1_lowest": "AV1 alone",
}
ROW_HEIGHT_PX = 288


def _panel(picture: np.ndarray, label: str) -> np.ndarray:
    import cv2

    bgr = cv2.cvtColor(picture, cv2.COLOR_YUV2BGR_I420)
    scale = ROW_HEIGHT_PX / bgr.shape[0]
    if scale != 1:
        size = (int(round(bgr.shape[1] * scale)), ROW_HEIGHT_PX)
        bgr = cv2.resize(bgr, size, interpolation=cv2.INTER_NEAREST)
    cv2.rectangle(bgr, (0, 0), (bgr.shape[1], 20), (0, 0, 0), thickness=-1)
    cv2.putText(bgr, label, (4, 15), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (255, 255, 255), 1)
    return bgr


def side_by_side(rows: list[tuple[str, dict[str, np.ndarray], dict[str, str]]]) -> np.ndarray:
    """BGR picture of `rows`: (clip name, YUV 4:2:0 picture per panel, label tail per panel)."""
    out = []
    for name, pictures, tails in rows:
        panels = [
            _panel(pictures[p], f"{name} {_LABELS[p]} {tails.get(p, '')}".strip())
            for p in PANELS
            if p in pictures
        ]
        gap = np.full((ROW_HEIGHT_PX, 4, 3), 255, np.uint8)
        row = np.concatenate([x for panel in panels for x in (panel, gap)][:-1], axis=1)
        out.append(row)
    width = max(r.shape[1] for r in out)
    padded = [
        np.pad(r, ((0, 4), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in out
    ]
    return np.concatenate(padded)[:-4]


def save_side_by_side(path: str | Path, rows) -> None:
    """Write `side_by_side(rows)` as a PNG, atomically."""
    import cv2

    from uma.atomic import atomic_write_bytes
    from uma.errors import UmaError

    ok, png = cv2.imencode(".png", side_by_side(rows), [cv2.IMWRITE_PNG_COMPRESSION, 9])
    if not ok:
        raise UmaError(f"{path}: cannot encode the picture as PNG")
    atomic_write_bytes(path, png.tobytes())
