"""Quickstart of uma's Python API: one scenario run two ways, plotted side by side.

The talking head at QCIF goes from WLAN into GSM (9.6 kbit/s) and back
(scenarios/wlan-gsm-wlan.yaml). Run once with H.264 alone and once with the UMA engine
switching to the model-based codec when the link collapses, then plot what the receiver saw.

    python examples/quickstart.py [OUT.png] [--duration-s S]

Writes OUT.png (default: quickstart.png in a new temporary folder) and prints its path.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import uma

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "wlan-gsm-wlan.yaml"
WAYS = {"H.264 alone": "none", "UMA: H.264, then the model codec": "threshold"}


def simulate(duration_s: float | None) -> dict[str, uma.Run]:
    keys = {} if duration_s is None else {"duration_s": duration_s}
    return {
        label: uma.run(SCENARIO, overrides={"engine.switching.policy": policy}, **keys)
        for label, policy in WAYS.items()
    }


def plot(runs: dict[str, uma.Run], png: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 6), layout="constrained")
    axes = fig.subplots(2, len(runs), sharex=True, sharey="row", squeeze=False)
    for column, (label, run) in enumerate(runs.items()):
        frames = run.frames  # a pandas DataFrame, units in the column names
        time_s = frames["display_ms"] / 1000.0
        top, bottom = axes[0][column], axes[1][column]
        top.plot(time_s, frames["psnr_db"], lw=1)
        top.fill_between(time_s, 0, 60, where=frames["frozen"] == 1, color="red", alpha=0.15)
        top.set_title(f"{label}\nfrozen {run.metrics['freeze_ratio']:.0%} of the time")
        sent_kbps = frames.groupby(frames["capture_ms"] // 1000)["size_bits"].sum() / 1000.0
        bottom.step(sent_kbps.index, sent_kbps, where="post", label="sent")
        capacity = frames.groupby(frames["capture_ms"] // 1000)["capacity_kbps"].mean()
        bottom.step(capacity.index, capacity, where="post", ls="--", label="capacity")
        bottom.set_yscale("log")
        bottom.set_xlabel("time (s)")
    axes[0][0].set_ylabel("PSNR (dB), red: frozen")
    axes[1][0].set_ylabel("kbit/s")
    axes[1][0].legend()
    fig.savefig(png, dpi=80)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("png", nargs="?", type=Path, help="where to write the plot")
    parser.add_argument("--duration-s", type=float, help="simulate only the first S seconds")
    args = parser.parse_args(argv)
    png = args.png or Path(tempfile.mkdtemp(prefix="uma-quickstart-")) / "quickstart.png"
    try:
        plot(simulate(args.duration_s), png)
    except uma.UmaError as err:  # bad input: one line, as the command line does
        print(f"quickstart: error: {err}", file=sys.stderr)
        return err.exit_code
    print(png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
