"""The readable table and the Salsify-style plot of `uma bench links`.

Units: delays in ms, rates in kbit/s, SSIM in dB. The plot puts the p95 delay on a reversed
log axis (better is right) against SSIM dB (better is up), one panel per trace, as Salsify's
figures do; matplotlib is imported only when a plot is drawn.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

__all__ = ["format_table", "save_plot"]

_NAMES = {"salsify_1c": "Salsify-1c", "webrtc": "WebRTC", "skype": "Skype", "facetime": "FaceTime"}


def _fmt(value: Any, spec: str) -> str:
    width = len(format(0.0, spec)) if "d" not in spec else len(format(0, spec))
    return f"{'n/a':>{width}}" if value is None else format(value, spec)


def _line(name: str, row: dict[str, Any]) -> str:
    return (
        f"    {name:<18}{_fmt(row['delay_p95_ms'], '9,.0f')}{_fmt(row['delay_median_ms'], '9,.0f')}"
        f"{_fmt(row['ssim_db'], '8.2f')}{_fmt(row['ssim_db_unfrozen'], '9.2f')}"
        f"{_fmt(row['freeze_ratio'], '8.3f')}{_fmt(row['kbps_video'], '9.1f')}"
        f"{_fmt(row['utilisation'], '7.2f')}{_fmt(row['keyframe_bits_share'], '7.2f')}"
    )


def format_table(result: dict[str, Any]) -> str:
    """One block per trace (a line per engine, then the published figures), then the medians."""
    head = (
        f"    {'engine':<18}{'p95 ms':>9}{'med ms':>9}{'SSIM dB':>8}{'unfrozen':>9}"
        f"{'frozen':>8}{'kbit/s':>9}{'sent/c':>7}{'key':>7}"
    )
    lines = [
        f"uma bench links: {result['scenario']} on {len(result['traces'])} traces, "
        f"first {result['duration_s']:g} s each",
        "  sent/c: sent over capacity; key: share of the bits in keyframes; published figures"
        " (publ.) are for each whole trace",
    ]
    for name, trace in result["traces"].items():
        lines += [
            "",
            f"  {name}: {trace['duration_s']:g} s, capacity {trace['capacity_kbps_mean']:,.0f} "
            "kbit/s mean",
            head,
        ]
        lines += [_line(engine, row) for engine, row in trace["engines"].items()]
        for size, bound in trace.get("bound", {}).items():
            lines.append(
                f"    {f'link bound, {size} B':<18}{_fmt(bound['delay_p95_ms'], '9,.0f')}"
                f"{_fmt(bound['delay_median_ms'], '9,.0f')}"
            )
        for system, figures in trace["published"].items():
            lines.append(
                f"    {_NAMES.get(system, system) + ' (publ.)':<18}"
                f"{figures['delay_p95_ms']:>9,.0f}{'':>9}{'':>8}{figures['ssim_db']:>9.1f}"
            )
    lines += ["", "  median over the traces", head]
    lines += [_line(engine, row) for engine, row in result["median"].items()]
    return "\n".join(lines)


def save_plot(result: dict[str, Any], path: Path) -> None:
    """p95 delay (reversed log axis) against SSIM dB, a panel per trace, written to `path`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, MaxNLocator, NullLocator

    traces = list(result["traces"].items())
    columns = min(4, max(1, len(traces)))
    rows = math.ceil(len(traces) / columns)
    figure, axes = plt.subplots(rows, columns, figsize=(3.2 * columns, 2.8 * rows), squeeze=False)
    markers = "osD^v<>"
    for index, (name, trace) in enumerate(traces):
        axis = axes[index // columns][index % columns]
        for k, (engine, row) in enumerate(trace["engines"].items()):
            if row["delay_p95_ms"] is None or row["ssim_db_unfrozen"] is None:
                continue
            axis.plot(
                max(row["delay_p95_ms"], 1.0), row["ssim_db_unfrozen"], markers[k % 7], label=engine
            )
        for system, figures in trace["published"].items():
            axis.plot(figures["delay_p95_ms"], figures["ssim_db"], "x", label=_NAMES.get(system))
        axis.set_xscale("log")
        # Three round values in plain ms: a narrow range's log ticks are labelled on top of
        # each other.
        axis.xaxis.set_major_locator(MaxNLocator(nbins=3))
        axis.xaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:,.0f}"))
        axis.xaxis.set_minor_locator(NullLocator())
        axis.invert_xaxis()
        axis.set_title(name[:32], fontsize=8)
        axis.set_xlabel("video delay p95 (ms)", fontsize=7)
        axis.set_ylabel("SSIM dB (unfrozen)", fontsize=7)
        axis.tick_params(labelsize=7)
        axis.legend(fontsize=6)
    for index in range(len(traces), rows * columns):
        axes[index // columns][index % columns].axis("off")
    figure.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(path.name + ".tmp.png")
    figure.savefig(temporary, dpi=110)
    plt.close(figure)
    temporary.replace(path)
