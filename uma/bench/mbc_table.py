"""`uma bench mbc`'s readable table (the JSON is `uma.bench.mbc.run_mbc_bench`'s)."""

from __future__ import annotations

from typing import Any

__all__ = ["format_table"]

REGIONS = ("face", "frame", "model")


def format_table(result: dict[str, Any]) -> str:
    lines = ["uma bench mbc: model-based codec, payload and wire rates at 25 frames/s", ""]
    head = (
        f"  {'clip':<14}{'frames':>7}{'size':>9}{'kbit/s':>8}{'wire':>7}{'loss dB':>8}"
        f"{'reinits':>8}{'track ms':>9}{'light ms':>9}{'init ms':>8}{'render ms':>10}"
        f"{'MDE px':>8}{'p95':>7}"
    )
    lines.append(head)

    def num(value, fmt):
        return "-" if value is None else format(value, fmt)

    for name, c in result["clips"].items():
        lines.append(
            f"  {name:<14}{c['frames']:>7}{c['size']:>9}{c['rate_kbps']:>8.2f}{c['wire_kbps']:>7.2f}"
            f"{c['psnr_loss_db']:>8.2f}{c['reinits']:>8}{num(c['track_ms_median'], '.1f'):>9}"
            f"{num(c['light_ms_median'], '.1f'):>9}{num(c['init_ms_median'], '.0f'):>8}"
            f"{num(c['render_ms_median'], '.2f'):>10}"
            f"{num(c['mde_median_px'], '.3f'):>8}{num(c['mde_p95_px'], '.3f'):>7}"
        )
    lines += [
        "",
        f"  {'clip':<14}{'display':<25}{'kbit/s':>7}  "
        + "".join(f"{r + ' PSNR':>11}{'SSIM':>7}{'CbCr':>6}" for r in REGIONS),
    ]
    for name, c in result["clips"].items():
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
    return "\n".join(lines)
