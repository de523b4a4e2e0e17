"""Replay a run's decode events through any adaptive playout, offline, in a second.

`python scripts/playout_replay.py FRAMES_CSV... [--set KEY=VALUE ...]` reads the `frames.csv`
of runs (`uma run --out DIR`, or any run's `FrameLog.to_csv()`) and replays each through the
adaptive playout of `receiver.adaptive` as the defaults and `--set` give it (`--set
reject_bursts=true --set calm_s=15`), beside the defaults alone. Decode events do not depend on
the playout (the receiver's display does not feed back to the sender), so the replay gives the
run's display instants, shown frames, frozen share and display-delay p95 to the digit: the first
column checks it against the run's own display (`display_ms`, `shown_frame`; a run made with
another playout differs there and only there). Per file and playout it prints the delay p95 and
median (ms), the frozen share and its display instants, and the instants shown over 1 s late.
SSIM and PSNR need the pictures, so they come from the simulation, not from here. The display
rule is `uma.sim.processes.display_process`'s: each instant asks the playout's delay, waits until
capture + delay (never back in time), and shows the newest frame decoded by then. Run from the
repository root with the checkout on `PYTHONPATH`.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import heapq
import sys
from pathlib import Path

import numpy as np
import pandas as pd
from pydantic import ValidationError

from uma.config.scenario import AdaptivePlayoutConfig
from uma.metrics.delay import display_delays_ms
from uma.sim.playout import AdaptivePlayout

__all__ = ["replay", "summarise", "main"]


def replay(frames: pd.DataFrame, playout: AdaptivePlayout, fps: float) -> dict[str, np.ndarray]:
    """The display instants (ms), shown frames and frozen flags of `frames` through `playout`."""
    capture_s = frames["capture_ms"].to_numpy() / 1000.0
    arrival_s = frames["arrival_ms"].to_numpy() / 1000.0
    decoded = frames["decoded"].to_numpy().astype(bool)
    scheduled = frames["scheduled"].to_numpy().astype(bool)
    # the receiver's technology at an instant: the one logged at the last capture by then
    technology = frames["technology"].fillna("").astype(str).to_numpy()
    order = [int(i) for i in np.argsort(arrival_s, kind="stable") if decoded[i]]
    count = len(frames)
    display_ms, shown, frozen = np.zeros(count), np.full(count, -1), np.zeros(count, dtype=int)
    held: list[int] = []  # decoded frames not yet let go, as a heap
    now_s, next_arrival, last_scheduled = 0.0, 0, -1

    def decode_until(until_s: float) -> None:
        nonlocal next_arrival
        while next_arrival < len(order) and arrival_s[order[next_arrival]] <= until_s:
            frame = order[next_arrival]
            playout.on_decoded(capture_s[frame], arrival_s[frame])
            heapq.heappush(held, frame)
            next_arrival += 1

    for index in range(count):
        decode_until(now_s)
        at = technology[max(0, int(np.searchsorted(capture_s, now_s, side="right")) - 1)]
        now_s = max(now_s, index / fps + playout.delay_s(now_s, at))
        decode_until(now_s)
        if scheduled[index]:
            last_scheduled = index
        candidates = [k for k in held if k <= index]
        if candidates:
            shown[index] = max(candidates)
            held[:] = [k for k in held if k >= shown[index]]
            heapq.heapify(held)
        display_ms[index] = now_s * 1000.0
        frozen[index] = int(shown[index] < 0 or shown[index] != last_scheduled)
    return {"display_ms": display_ms, "shown_frame": shown, "frozen": frozen}


def summarise(frames: pd.DataFrame, shown: dict[str, np.ndarray]) -> str:
    """p95 and median display delay, frozen share and instants, instants over 1 s: one line."""
    delays = display_delays_ms(
        frames["capture_ms"].to_numpy(), shown["display_ms"], shown["shown_frame"]
    )
    frozen = shown["frozen"]
    return (
        f"p95 {np.percentile(delays, 95):9.3f} ms, median {np.median(delays):8.3f} ms, "
        f"frozen {frozen.mean():.4f} ({int(frozen.sum())}), over 1 s {int((delays > 1000).sum())}"
    )


def _config(pairs: list[str]) -> AdaptivePlayoutConfig:
    """`receiver.adaptive` from the defaults and KEY=VALUE pairs (values as YAML reads them)."""
    import yaml

    updates = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep:
            raise ValueError(f"--set: expected KEY=VALUE, got {pair!r}")
        updates[key] = yaml.safe_load(value)
    return AdaptivePlayoutConfig.model_validate(updates)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("frames", nargs="+", type=Path, help="a run's frames.csv")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--initial-delay-ms", type=float, default=300.0)
    args = parser.parse_args(argv)
    try:
        variants = {"defaults": _config([]), "with --set": _config(args.set)}
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(["receiver.adaptive", *(str(part) for part in first["loc"])])
        print(f"playout_replay: {where}: {first['msg']}", file=sys.stderr)
        return 2
    except ValueError as error:
        print(f"playout_replay: {error}".splitlines()[0], file=sys.stderr)
        return 2
    for path in args.frames:
        frames = pd.read_csv(path)
        fps = 1000.0 / float(np.median(np.diff(frames["capture_ms"].to_numpy())))
        print(f"{path}  ({len(frames)} instants at {fps:g} fps)")
        for name, config in variants.items():
            playout = AdaptivePlayout(config, initial_delay_s=args.initial_delay_ms / 1000.0)
            shown = replay(frames, playout, fps)
            same = np.array_equal(shown["shown_frame"], frames["shown_frame"].to_numpy())
            diff_ms = float(np.abs(shown["display_ms"] - frames["display_ms"].to_numpy()).max())
            check = f"as the run (display within {diff_ms:.2g} ms)" if same else "not as the run"
            print(f"  {name:10s} {summarise(frames, shown)}  [{check}]")
    return 0


if __name__ == "__main__":
    sys.exit(main())
