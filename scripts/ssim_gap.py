"""Where the unfrozen-SSIM gap between two engines of `uma bench links`' scenario comes from.

`python scripts/ssim_gap.py --case TRACE:OFFSET_S:DURATION_S [--engines uma,gcc] [--engine
KEY=JSON ...] [--workers 2] [--bin-s 2] [--top 10] [--out DIR]` runs each case and engine as
`scripts/links_settings.py` does (the Salsify scenario through `uma.bench.links.link_task`, seed
0; the rows are the bench's), keeps each run's frame log in `DIR/TRACE-OFFSET-ENGINE.npz`
(`--reuse` reads them instead of running again) and prints, per engine: kbit/s sent against
the capacity and the estimate, frames coded a second, keyframes and their share of the bits,
frames skipped, rung and size changes among the frames sent; and per rung (the rung of the
frame shown): its share of all instants (the rung decided at capture) and of the unfrozen ones,
and the mean SSIM (dB of the mean) of the unfrozen instants showing it. Then, for the first two
engines (A, B), the gap in the mean unfrozen SSIM taken apart:

- by instants: both unfrozen (the common instants: A's and B's pictures of the same source
  frame), A only, B only; each engine's mean is its common instants' and its own instants';
- on the common instants, by the two rungs shown (A lower, equal, higher) and by what A shows
  (a keyframe or a frame within 1 s of a size change);
- a shift-share split of the whole gap: the rung mix (A's shares against B's, at B's mean per
  rung) and the quality within a rung (at A's shares);
- the bins (`--bin-s`) whose common instants lose most, with the capacity, both estimates,
  both sent rates and rungs, and A's keyframes and size changes there.

SSIM is averaged linearly and shown as dB of the mean, as the bench's `ssim_db_unfrozen` is.
Run from the repository root with the checkout on `PYTHONPATH`.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import json
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from links_settings import add_case_arguments, case_task, cases, json_keys  # scripts/

KEEP = (
    "capture_ms", "capacity_kbps", "estimate_kbps", "rung", "width", "scheduled", "sent",
    "keyframe", "size_bits", "shown_frame", "frozen", "ssim",
)  # fmt: skip


def db(ssim: float) -> float:
    """SSIM in dB (-10 log10(1 - SSIM)); NaN for no instants."""
    return float("nan") if not np.isfinite(ssim) else -10.0 * np.log10(max(1.0 - ssim, 1e-9))


def _run(job: tuple) -> str:
    trace, offset_s, duration_s, engine, engine_keys, path = job
    from uma.bench.links import row_of
    from uma.config.scenario import Scenario
    from uma.sim import run_scenario
    from uma.sim.summary import run_metrics

    task = case_task(trace, offset_s, duration_s, engine, engine_keys)
    result = run_scenario(Scenario.model_validate(task["scenario"]))
    metrics = run_metrics(result)
    row = row_of(result, metrics)
    extra = dict(skipped=metrics.get("skipped_frames", 0), duration_s=duration_s)
    arrays = {name: np.asarray(result.log[name]) for name in KEEP}
    np.savez(path, row=np.array(json.dumps({**row, **extra})), **arrays)
    return path


def load(path: str) -> dict:
    """A kept run: its log columns and `row` (the bench's row, `skipped`, `duration_s`)."""
    with np.load(path) as data:
        run = {name: data[name] for name in KEEP}
        run["row"] = json.loads(str(data["row"]))
    shown = run["shown_frame"]
    ok = shown >= 0
    for name in ("rung", "width", "keyframe", "size_bits"):
        column = np.full(len(shown), -1, dtype=run[name].dtype)
        column[ok] = run[name][shown[ok]]
        run["shown_" + name] = column
    run["fresh"] = (run["frozen"] == 0) & np.isfinite(run["ssim"]) & ok
    return run


def changes(run: dict) -> tuple[int, int]:
    """Rung changes and size changes among the frames sent, in order."""
    sent = run["sent"] > 0
    rungs, widths = run["rung"][sent], run["width"][sent]
    return int((np.diff(rungs) != 0).sum()), int((np.diff(widths) != 0).sum())


def near_size_change(run: dict, within_frames: int = 25) -> np.ndarray:
    """Per instant: the frame shown was sent within `within_frames` of a change of size."""
    sent = np.flatnonzero(run["sent"] > 0)
    widths = run["width"][sent]
    starts = sent[1:][np.diff(widths) != 0]
    near = np.zeros(len(run["sent"]), dtype=bool)
    for start in starts:
        near[start : start + within_frames] = True
    shown = run["shown_frame"]
    return np.where(shown >= 0, near[np.clip(shown, 0, None)], False)


def summary(name: str, run: dict) -> None:
    """One engine's rates, keyframes, skips, changes and per-rung table."""
    row, sent = run["row"], run["sent"] > 0
    duration_s = run["row"]["duration_s"]
    bits = run["size_bits"][sent].astype(float)
    key = run["keyframe"][sent] > 0
    rung_changes, size_changes = changes(run)
    print(
        f"{name}: p95 {row['delay_p95_ms']:.0f} ms, SSIM unfrozen {row['ssim_db_unfrozen']:.2f} "
        f"dB, frozen {row['freeze_ratio']:.4f}, utilisation {row['utilisation']:.3f}; video "
        f"{bits.sum() / duration_s / 1000:.1f} kbit/s, capacity "
        f"{np.nanmean(run['capacity_kbps']):.0f}, estimate mean "
        f"{np.nanmean(run['estimate_kbps']):.0f} median {np.nanmedian(run['estimate_kbps']):.0f}; "
        f"coded {sent.sum() / duration_s:.2f}/s, keyframes {key.sum()} "
        f"({bits[key].sum() / max(bits.sum(), 1):.3f} of bits), skipped {row['skipped']}, "
        f"rung changes {rung_changes}, size changes {size_changes}"
    )
    fresh, total = run["fresh"], len(run["fresh"])
    print("   rung  size  time  unfrozen  SSIM dB  (keyframe shown: share, dB)")
    for rung in sorted(set(run["rung"][run["rung"] >= 0]) | set(run["shown_rung"][fresh])):
        on = fresh & (run["shown_rung"] == rung)
        keyed = on & (run["shown_keyframe"] > 0)
        width = run["width"][run["rung"] == rung]
        print(
            f"   {rung:4d} {int(width.max()) if width.size else -1:5d} "
            f"{(run['rung'] == rung).sum() / total:5.3f} {on.sum() / total:8.3f} "
            f"{db(run['ssim'][on].mean()) if on.any() else float('nan'):8.2f}  "
            f"({keyed.sum() / max(on.sum(), 1):.3f}, "
            f"{db(run['ssim'][keyed].mean()) if keyed.any() else float('nan'):.2f})"
        )


def _mean(values: np.ndarray) -> float:
    return float(values.mean()) if values.size else float("nan")


def instants(a: dict, b: dict) -> np.ndarray:
    """The gap by instants: both unfrozen, A only, B only; returns the common mask."""
    fa, fb = a["fresh"], b["fresh"]
    both = fa & fb
    print(
        f"gap {db(_mean(a['ssim'][fa])) - db(_mean(b['ssim'][fb])):+.2f} dB "
        f"(A {db(_mean(a['ssim'][fa])):.2f}, B {db(_mean(b['ssim'][fb])):.2f})"
    )
    for label, mask in (("both", both), ("A only", fa & ~fb), ("B only", fb & ~fa)):
        print(
            f"   {label:7s} share of A's {mask[fa].mean() if label != 'B only' else 0:.3f} "
            f"of B's {mask[fb].mean() if label != 'A only' else 0:.3f}: "
            f"A {db(_mean(a['ssim'][mask & fa])):6.2f} dB, B {db(_mean(b['ssim'][mask & fb])):6.2f}"
        )
    return both


def common(a: dict, b: dict, both: np.ndarray) -> None:
    """On the common instants: the gap by the rungs shown, keyframes, size changes."""
    ra, rb = a["shown_rung"], b["shown_rung"]
    d = a["ssim"] - b["ssim"]
    n = max(both.sum(), 1)
    near_a = near_size_change(a)
    classes = (
        ("A lower rung", both & (ra < rb)),
        ("same rung", both & (ra == rb)),
        ("A higher rung", both & (ra > rb)),
        ("A shows keyframe", both & (a["shown_keyframe"] > 0)),
        ("B shows keyframe", both & (b["shown_keyframe"] > 0)),
        ("A <1 s after size change", both & near_a),
        ("A lower, B estimate > A's", both & (ra < rb) & (b["estimate_kbps"] > a["estimate_kbps"])),
    )
    print("   common instants by class: share, A dB, B dB, contribution to the mean SSIM gap")
    for label, mask in classes:
        print(
            f"   {label:26s} {mask.sum() / n:5.3f} {db(_mean(a['ssim'][mask])):6.2f} "
            f"{db(_mean(b['ssim'][mask])):6.2f} {d[mask].sum() / n:+.4f}"
        )


def shift_share(a: dict, b: dict) -> None:
    """The whole gap (linear SSIM) as the rung mix at B's quality plus quality at A's mix."""
    fa, fb = a["fresh"], b["fresh"]
    mix = within = 0.0
    for rung in sorted(set(a["shown_rung"][fa]) | set(b["shown_rung"][fb])):
        on_a, on_b = fa & (a["shown_rung"] == rung), fb & (b["shown_rung"] == rung)
        wa, wb = on_a.sum() / fa.sum(), on_b.sum() / fb.sum()
        qa, qb = _mean(a["ssim"][on_a]), _mean(b["ssim"][on_b])
        if not on_b.any():  # a rung B never shows: at A's quality, all of it mix
            mix += wa * qa
            continue
        mix += (wa - wb) * qb
        within += wa * (qa - qb) if on_a.any() else 0.0
    gap = _mean(a["ssim"][fa]) - _mean(b["ssim"][fb])
    print(f"   mean SSIM gap {gap:+.4f}: rung mix {mix:+.4f}, within rungs {within:+.4f}")


def bins(a: dict, b: dict, both: np.ndarray, bin_s: float, top: int) -> None:
    """The bins whose common instants lose most, with what both engines did there."""
    t = a["capture_ms"] / 1000.0
    index = np.floor(t / bin_s).astype(int)
    d = np.where(both, a["ssim"] - b["ssim"], 0.0)
    n = max(both.sum(), 1)
    loss = np.bincount(index, weights=d) / n
    near_a = near_size_change(a)
    print(f"   bins of {bin_s:g} s losing most (contribution; cap, est A/B, sent A/B, rung A/B)")
    for k in np.argsort(loss)[:top]:
        rows = index == k
        sent_a = a["size_bits"][rows & (a["sent"] > 0)].sum() / bin_s / 1000
        sent_b = b["size_bits"][rows & (b["sent"] > 0)].sum() / bin_s / 1000
        keys = int((a["keyframe"][rows & (a["sent"] > 0)] > 0).sum())
        print(
            f"   {k * bin_s:6.0f} s {loss[k]:+.4f} cap {np.nanmean(a['capacity_kbps'][rows]):6.0f} "
            f"est {np.nanmedian(a['estimate_kbps'][rows]):5.0f}/"
            f"{np.nanmedian(b['estimate_kbps'][rows]):5.0f} sent {sent_a:5.0f}/{sent_b:5.0f} "
            f"rung {np.median(a['shown_rung'][rows & both]) if (rows & both).any() else -1:.0f}/"
            f"{np.median(b['shown_rung'][rows & both]) if (rows & both).any() else -1:.0f} "
            f"A keyframes {keys} near size change {(near_a & rows & both).sum()}"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_case_arguments(parser, "uma,gcc")
    parser.add_argument("--out", default="/tmp/ssim_gap")
    parser.add_argument("--reuse", action="store_true")
    parser.add_argument("--bin-s", type=float, default=2.0)
    parser.add_argument("--top", type=int, default=10)
    args = parser.parse_args(argv)
    engine_keys = json_keys(args.engine)
    Path(args.out).mkdir(parents=True, exist_ok=True)
    jobs = [
        (*case, engine_keys, str(Path(args.out, f"{Path(case[0]).stem}-{case[1]:g}-{case[3]}.npz")))
        for case in cases(args)
    ]
    if not args.reuse:
        with ProcessPoolExecutor(args.workers) as pool:
            list(pool.map(_run, jobs))
    engines = args.engines.split(",")
    for start in range(0, len(jobs), len(engines)):
        runs = [load(job[-1]) for job in jobs[start : start + len(engines)]]
        print(f"== {Path(jobs[start][0]).stem} {jobs[start][1]:g}+{jobs[start][2]:g} s")
        for engine, run in zip(engines, runs, strict=True):
            summary(engine, run)
        if len(runs) >= 2:
            both = instants(runs[0], runs[1])
            common(runs[0], runs[1], both)
            shift_share(runs[0], runs[1])
            bins(runs[0], runs[1], both, args.bin_s, args.top)
    return 0


if __name__ == "__main__":
    sys.exit(main())
