"""A side-by-side PNG of the source and what the receiver showed at one display instant, for
one or more scenarios run to that instant (docs/refresh-gprs.png).

Units: times in seconds.

    python -m uma.report.snapshot SCENARIO [SCENARIO ...] --at-s 75 --out docs/refresh-gprs.png

Each scenario is simulated until the instant `at_s` is displayed (the run stops there); the
picture is the source frame of that instant, then each run's shown picture labelled with its
scenario's name, the codec shown and whether the display was frozen, and its face-box PSNR
and SSIM (luma, limited range, over the source's face box of `uma/face/region.py`, scored by
`uma.metrics.region_scores` as the simulation scores it).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
from pathlib import Path

import numpy as np

__all__ = ["capture", "snapshot_png", "main"]


class _Captured(Exception):
    """Stops a run once the instant wanted was displayed."""


def capture(scenario, at_s: float) -> tuple[np.ndarray, np.ndarray | None, int]:
    """Run `scenario` to the display instant at `at_s`: (source, shown picture or None, the
    source frame shown)."""
    from uma.sim import run_scenario

    index = int(round(at_s * scenario.source.fps))
    found: list = []

    def on_display(i: int, source: np.ndarray, shown: int, picture) -> None:
        if i == index:
            found.append((source.copy(), None if picture is None else picture.copy(), shown))
            raise _Captured

    with contextlib.suppress(_Captured):
        run_scenario(scenario, on_display=on_display)
    if not found:
        raise ValueError(f"{scenario.name}: no display instant at {at_s:g} s (the run is shorter)")
    return found[0]


def _bgr(yuv: np.ndarray, width: int, height: int) -> np.ndarray:
    import cv2

    bgr = cv2.cvtColor(yuv, cv2.COLOR_YUV2BGR_I420)
    if bgr.shape[:2] != (height, width):
        bgr = cv2.resize(bgr, (width, height), interpolation=cv2.INTER_LINEAR)
    return bgr


def _label(image: np.ndarray, lines: list[str]) -> None:
    import cv2

    for i, text in enumerate(lines):
        y = 16 + 16 * i
        cv2.putText(image, text, (5, y), cv2.FONT_HERSHEY_SIMPLEX, 0.42, (0, 0, 0), 3, cv2.LINE_AA)
        cv2.putText(image, text, (5, y), cv2.FONT_HERSHEY_SIMPLEX, 0.42, (255, 255, 255), 1,
                    cv2.LINE_AA)  # fmt: skip


def _face_scores(source: np.ndarray, picture: np.ndarray, box) -> tuple[float, float]:
    from uma.metrics import region_scores

    height = source.shape[0] * 2 // 3
    return region_scores(source[:height], picture[:height], box)


def snapshot_png(scenarios, at_s: float, out: str | Path, *, labels=None) -> Path:
    """Write the PNG for `scenarios` (loaded `Scenario`s) at `at_s`; returns its path."""
    import cv2

    from uma.atomic import atomic_open
    from uma.face.region import FaceBoxes
    from uma.sim.sources import open_source

    panels, source = [], None
    for k, scenario in enumerate(scenarios):
        frame, picture, shown = capture(scenario, at_s)
        height, width = frame.shape[0] * 2 // 3, frame.shape[1]
        if source is None:
            source = _bgr(frame, width, height)
            _label(source, ["source", f"{at_s:g} s"])
            boxes = FaceBoxes(open_source(scenario.source, seed=scenario.seed))
            box = boxes.box(int(round(at_s * scenario.source.fps)), frame)
            if box is not None:
                cv2.rectangle(source, (box.x, box.y), (box.x + box.width, box.y + box.height),
                              (0, 200, 0), 1)  # fmt: skip
        scores = None
        if picture is not None:
            from uma.video import resize_yuv420

            picture = resize_yuv420(picture, width, height)  # a lower rung is shown upscaled
            scores = _face_scores(frame, picture, box)
        panel = np.zeros_like(source) if picture is None else _bgr(picture, width, height)
        name = labels[k] if labels else scenario.name
        index = int(round(at_s * scenario.source.fps))
        state = "frozen" if shown != index else "live"
        lines = [name, f"shows frame {shown} ({state})"]
        if scores is not None and np.isfinite(scores[0]):
            lines.append(f"face {scores[0]:.1f} dB / {scores[1]:.3f}")
        _label(panel, lines)
        panels.append(panel)
    ok, png = cv2.imencode(".png", np.hstack([source, *panels]))
    if not ok:
        raise ValueError(f"{out}: the PNG could not be encoded")
    out = Path(out)
    with atomic_open(out, "wb") as handle:
        handle.write(png.tobytes())
    return out


def main(argv: list[str] | None = None) -> int:
    from uma.config import load_scenario
    from uma.errors import UmaError

    parser = argparse.ArgumentParser(prog="python -m uma.report.snapshot", description=__doc__)
    parser.add_argument("scenarios", nargs="+", help="scenario YAML files")
    parser.add_argument("--at-s", type=float, required=True, help="display instant, seconds")
    parser.add_argument("--out", required=True, help="PNG to write")
    parser.add_argument("--labels", help="comma-separated panel labels (default: names)")
    args = parser.parse_args(argv)
    labels = args.labels.split(",") if args.labels else None
    if labels is not None and len(labels) != len(args.scenarios):
        parser.error(f"--labels: expected {len(args.scenarios)} labels, got {len(labels)}")
    try:
        scenarios = [load_scenario(path) for path in args.scenarios]
        print(snapshot_png(scenarios, args.at_s, args.out, labels=labels))
    except (UmaError, ValueError, OSError) as err:
        print(f"uma: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
