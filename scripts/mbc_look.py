"""Look at one clip's MBC pictures up close: source | MBC | MBC + refresh, enlarged.

    PYTHONPATH=$PWD python scripts/mbc_look.py carphone out.png [--frame N] [--scale 4]
        [--start 0] [--frames 150]

runs `uma.bench.mbc.run_clip` on the clip (the default refresh displays) and writes the
panels of frame N (default: the largest head motion, as `uma bench mbc --picture`), each
enlarged `scale` times (nearest neighbour) so seams and smears are seen pixel by pixel.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse


def main() -> None:
    import cv2
    import numpy as np

    from uma.bench import mbc
    from uma.bench.mbc_clips import default_clips

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("clip")
    parser.add_argument("out")
    parser.add_argument("--frame", type=int, default=mbc.LARGEST_MOTION)
    parser.add_argument("--scale", type=int, default=4)
    parser.add_argument("--start", type=int, default=0)
    parser.add_argument("--frames", type=int, default=150)
    parser.add_argument("--panels", default="source,quantised,mbc_refresh_lowest")
    args = parser.parse_args()
    clip = next(c for c in default_clips(args.frames, start=args.start) if c.name == args.clip)
    kept: dict = {}
    result = mbc.run_clip(clip, keep_frame=args.frame, kept=kept)
    panels = []
    for name in args.panels.split(","):
        bgr = cv2.cvtColor(kept[name], cv2.COLOR_YUV2BGR_I420)
        bgr = cv2.resize(bgr, None, fx=args.scale, fy=args.scale, interpolation=cv2.INTER_NEAREST)
        panels += [bgr, np.full((bgr.shape[0], 4, 3), 255, np.uint8)]
    cv2.imwrite(args.out, np.concatenate(panels[:-1], axis=1))
    face = result["face"]
    print(f"{clip.name} #{result['kept_frame']}: " + ", ".join(
        f"{n} {face[n]['psnr_db']:.2f} dB" for n in ("quantised", "mbc_refresh_lowest")
    ))  # fmt: skip


if __name__ == "__main__":
    main()
