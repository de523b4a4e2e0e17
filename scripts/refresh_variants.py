"""What a model-aided refresh should code: `uma bench mbc`'s refresh displays for other specs.

    PYTHONPATH=$PWD python scripts/refresh_variants.py [--start 150] [--frames 150]
        [--set box|residual|preset|codec|fresh] [--clips akiyo,carphone]

codes akiyo and carphone (frames `start` to `start + frames`: 150-299 by default, the tuning
frames the bench does not quote) with the MBC plus each refresh variant below at the two
lowest rungs' total rates, and prints per clip and variant the face box luma PSNR dB, SSIM,
whole-frame SSIM and total kbit/s, beside the plain MBC, H.264 and AV1 (docs/refresh.md).
"""

from __future__ import annotations

import argparse


def variants() -> dict:
    """name -> `uma.bench.mbc_refresh.RefreshSpec`: the face box at 1/2, 3/4 and full scale,
    at the rung's frame rate or half of it, and the whole picture."""
    from uma.bench.mbc_refresh import RefreshSpec

    out = {}
    for rung, fps in ((0, 5.0), (1, 25 / 3)):
        out[f"box0.5_r{rung}"] = RefreshSpec(rung, fps, region="face", face_scale=0.5)
        out[f"box0.75_r{rung}"] = RefreshSpec(rung, fps, region="face", face_scale=0.75)
        out[f"box1.0_half_fps_r{rung}"] = RefreshSpec(rung, fps / 2, region="face", face_scale=1)
        out[f"box0.5_half_fps_r{rung}"] = RefreshSpec(rung, fps / 2, region="face", face_scale=0.5)
        out[f"frame_half_fps_r{rung}"] = RefreshSpec(rung, fps / 2, region="frame")
        out[f"frame176_r{rung}"] = RefreshSpec(rung, fps, region="frame", size=(176, 144))
    return out


def residual_variants() -> dict:
    """name -> `RefreshSpec`: the face box at 1/2 scale (the default) against the residual
    against the MBC rendering in that box, as a P chain or intra every unit, at 1/2 and 3/4
    scale."""
    from uma.bench.mbc_refresh import RefreshSpec

    out = {}
    for rung, fps in ((0, 5.0), (1, 25 / 3)):
        out[f"box0.5_r{rung}"] = RefreshSpec(rung, fps, region="face", face_scale=0.5)
        for scale in (0.5, 0.75):
            out[f"residual{scale:g}_p_r{rung}"] = RefreshSpec(
                rung, fps, region="residual", face_scale=scale
            )
            out[f"residual{scale:g}_intra_r{rung}"] = RefreshSpec(
                rung, fps, region="residual", face_scale=scale, intra_every_unit=True
            )
    return out


def preset_variants() -> dict:
    """name -> `RefreshSpec`: the face box at 1/2 scale (the default) at libx264's presets."""
    from uma.bench.mbc_refresh import RefreshSpec

    out = {}
    for rung, fps in ((0, 5.0), (1, 25 / 3)):
        for preset in ("ultrafast", "veryfast", "medium", "slow"):
            out[f"box0.5_{preset}_r{rung}"] = RefreshSpec(
                rung, fps, region="face", face_scale=0.5, preset=preset
            )
    return out


def codec_variants() -> dict:
    """name -> `RefreshSpec`: the face box at 1/2 scale coded by libx264 (the default), by
    SVT-AV1 at its ladder's preset 12 and at 10, and by libvpx VP8."""
    from uma.bench.mbc_refresh import RefreshSpec

    out = {}
    for rung, fps in ((0, 5.0), (1, 25 / 3)):
        out[f"box0.5_h264_r{rung}"] = RefreshSpec(
            rung, fps, region="face", face_scale=0.5, preset="medium"
        )
        out[f"box0.5_av1_r{rung}"] = RefreshSpec(rung, fps, region="face", face_scale=0.5,
                                                 codec="av1")  # fmt: skip
        out[f"box0.5_av1p10_r{rung}"] = RefreshSpec(
            rung, fps, region="face", face_scale=0.5, codec="av1", preset=10
        )
        out[f"box0.5_vp8_r{rung}"] = RefreshSpec(rung, fps, region="face", face_scale=0.5,
                                                 codec="vp8")  # fmt: skip
    return out


def fresh_variants() -> dict:
    """name -> `RefreshSpec`: how fresh against how many bits (session refresh2): the previous
    default (half the box at the rung's frame rate, the ladder's VBV of 4 frames), a VBV of 1
    frame, 12.5 and 25 frames/s, the box at 0.625 and 0.75, the rate asked 1.25x the budget,
    and SVT-AV1 and VP8 at 12.5 frames/s (AV1 asked 0.8x: its CBR overshoots)."""
    from uma.bench.mbc_refresh import PREVIOUS_REFRESH, RefreshSpec

    out = {f"previous_r{k}": spec for k, spec in enumerate(PREVIOUS_REFRESH.values())}
    for rung in (0, 1):
        fps = (5.0, 25 / 3)[rung]
        fast = {"region": "face", "face_scale": 0.5, "preset": "medium", "vbv_frames": 2.0}
        out[f"vbv1_r{rung}"] = RefreshSpec(rung, fps, region="face", face_scale=0.5,
                                           preset="medium", vbv_frames=1.0)  # fmt: skip
        out[f"f12.5_r{rung}"] = RefreshSpec(rung, 12.5, **fast)
        out[f"f25_r{rung}"] = RefreshSpec(rung, 25.0, **fast)
        out[f"f12.5_gain1.25_r{rung}"] = RefreshSpec(rung, 12.5, rate_gain=1.25, **fast)
        for scale in (0.625, 0.75):
            out[f"f12.5_s{scale:g}_r{rung}"] = RefreshSpec(
                rung, 12.5, **{**fast, "face_scale": scale}
            )
        out[f"f12.5_av1_r{rung}"] = RefreshSpec(
            rung, 12.5, region="face", face_scale=0.625, codec="av1", preset=8, vbv_frames=1.0,
            rate_gain=0.8,
        )  # fmt: skip
        out[f"f12.5_vp8_r{rung}"] = RefreshSpec(
            rung, 12.5, region="face", face_scale=0.5, codec="vp8", vbv_frames=2.0
        )
    return out


def main() -> None:
    from uma.bench import mbc
    from uma.bench.mbc_clips import default_clips

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--start", type=int, default=150)
    parser.add_argument("--frames", type=int, default=150)
    parser.add_argument(
        "--set", choices=("box", "residual", "preset", "codec", "fresh"), default="box"
    )
    parser.add_argument("--clips", default="akiyo,carphone")
    args = parser.parse_args()
    specs = {
        "box": variants,
        "residual": residual_variants,
        "preset": preset_variants,
        "codec": codec_variants,
        "fresh": fresh_variants,
    }[args.set]()
    shown = [*specs, "quantised", "h264_lowest", "h264_second", "av1_lowest", "av1_second"]
    for clip in default_clips(args.frames, start=args.start):
        if clip.name not in args.clips.split(","):
            continue
        result = mbc.run_clip(clip, refresh=specs)
        for name in shown:
            face, frame = result["face"][name], result["frame"][name]
            print(f"{clip.name} {name}: {face['psnr_db']:.2f} dB / {face['ssim']:.3f}, "
                  f"frame SSIM {frame['ssim']:.3f}, {face['kbps']:.1f} kbit/s")  # fmt: skip


if __name__ == "__main__":
    main()
