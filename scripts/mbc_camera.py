"""The camera's motion on and off, side by side: `uma bench mbc`'s figures for each clip.

    PYTHONPATH=$PWD python scripts/mbc_camera.py [--start 150] [--frames 150] [--clips akiyo,carphone]

prints per clip and setting the MBC alone (face box PSNR dB / SSIM, whole-frame SSIM, kbit/s)
and MBC plus refresh at the two lowest rungs (face box, whole-frame SSIM, total kbit/s).
Frames 150-299 (the default) are the tuning frames; quote on `--start 0` and foreman.
"""

from __future__ import annotations

import argparse

SHOWN = ("quantised", "mbc_refresh_lowest", "mbc_refresh_second", "h264_lowest")


def main() -> None:
    from uma.bench import mbc
    from uma.bench.mbc_clips import default_clips

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--start", type=int, default=150)
    parser.add_argument("--frames", type=int, default=150)
    parser.add_argument("--clips", default="akiyo,carphone")
    parser.add_argument("--settings", default="off,on", help="camera motion off and/or on")
    args = parser.parse_args()
    for clip in default_clips(args.frames, start=args.start):
        if clip.name not in args.clips.split(","):
            continue
        for setting in args.settings.split(","):
            result = mbc.run_clip(clip, camera=setting == "on")
            for name in SHOWN:
                face, frame = result["face"][name], result["frame"][name]
                print(f"{clip.name} camera {setting} {name}: {face['psnr_db']:.2f} dB / "
                      f"{face['ssim']:.3f}, frame SSIM {frame['ssim']:.3f}, "
                      f"{face['kbps']:.2f} kbit/s", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
