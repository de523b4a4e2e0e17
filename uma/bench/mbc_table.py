"""`uma bench mbc`'s readable table (the JSON is `uma.bench.mbc.run_model_bench`'s)."""

from __future__ import annotations

from typing import Any

import numpy as np

from uma.codecs import model_names, spec

__all__ = ["format_table", "summarise"]

REGIONS = ("face", "frame", "model")


def format_table(result: dict[str, Any]) -> str:
    model = spec(model_names()[0])
    lines = [
        f"uma bench {model.name}: {model.label} codec, payload and wire rates at 25 frames/s",
        "",
    ]
    head = (
        f"  {'clip':<14}{'frames':>7}{'size':>9}{'kbit/s':>8}{'wire':>7}{'loss dB':>8}"
        f"{'reinits':>8}{'track ms':>9}{'light ms':>9}{'body ms':>8}{'init ms':>8}"
        f"{'render ms':>10}{'refresh':>8}{'path ms':>8}{'MDE px':>8}{'p95':>7}"
    )
    lines.append(head)

    def num(value, fmt):
        return "-" if value is None else format(value, fmt)

    for name, c in result["clips"].items():
        lines.append(
            f"  {name:<14}{c['frames']:>7}{c['size']:>9}{c['rate_kbps']:>8.2f}{c['wire_kbps']:>7.2f}"
            f"{c['psnr_loss_db']:>8.2f}{c['reinits']:>8}{num(c['track_ms_median'], '.1f'):>9}"
            f"{num(c['light_ms_median'], '.1f'):>9}{num(c.get('body_ms_median'), '.1f'):>8}"
            f"{num(c['init_ms_median'], '.0f'):>8}{num(c['render_ms_median'], '.2f'):>10}"
            f"{num(c.get('stages_ms', {}).get('refresh'), '.2f'):>8}"
            f"{num(c.get('model_path_ms'), '.1f'):>8}"
            f"{num(c['mde_median_px'], '.3f'):>8}{num(c['mde_p95_px'], '.3f'):>7}"
        )
    lines += [
        "",
        f"  {'clip':<14}{'display':<25}{'kbit/s':>7}  "
        + "".join(f"{r + ' PSNR':>11}{'SSIM':>7}{'CbCr':>6}" for r in REGIONS),
    ]
    for name, c in result["clips"].items():
        if c.get("kind", "real clip") != "real clip":
            lines.append(f"  {name}: {c['kind']} (flatters a model codec; not in the summary)")
        for d in c["face"]:
            rung = c.get(d.removesuffix("_delayed"), {}).get("rung")
            label = d if not rung else f"{d} {rung.split()[0]}"
            kbps = c["face"][d].get("kbps")
            cells = "".join(
                f"{c[r][d]['psnr_db']:>11.2f}{c[r][d]['ssim']:>7.3f}"
                f"{c[r][d]['chroma_psnr_db']:>6.1f}"
                for r in REGIONS
            )
            lines.append(f"  {name:<14}{label:<25}{num(kbps, '.2f'):>7}  {cells}")
    summary = result.get("summary_real_clips", {})
    if len(summary) > 1:
        lines += ["", f"  real clips only ({', '.join(summary['clips'])}): mean of the clips",
                  f"  {'display':<25}{'face PSNR':>10}{'SSIM':>7}{'frame PSNR':>11}{'SSIM':>7}"]  # fmt: skip
        for d, v in summary.items():
            if d != "clips":
                lines.append(f"  {d:<25}{v['face_psnr_db']:>10.2f}{v['face_ssim']:>7.3f}"
                             f"{v['frame_psnr_db']:>11.2f}{v['frame_ssim']:>7.3f}")  # fmt: skip
    return "\n".join(lines)


def summarise(clips: dict[str, dict], model_own: str) -> dict[str, Any]:
    """Per display, the mean face and whole-frame PSNR and SSIM over the real clips only (not
    those of kind `model_own`, the model's own rendering), and the clips it was taken over."""
    real = [c for c in clips.values() if c.get("kind") != model_own]
    out: dict[str, Any] = {"clips": [n for n, c in clips.items() if c.get("kind") != model_own]}
    if not real:
        return out
    for display in real[0]["face"]:
        out[display] = {
            f"{region}_{key}": round(float(np.mean([c[region][display][key] for c in real])), 4)
            for region in ("face", "frame")
            for key in ("psnr_db", "ssim")
        }
    return out
