"""Where the display delay's tail of `uma bench links`' scenario lies, per engine.

`python scripts/delay_tail.py --case TRACE:OFFSET_S:DURATION_S [--engines uma,gcc,oracle]
[--engine KEY=JSON ...] [--workers 2] [--out DIR]` runs each case and engine as
`scripts/links_settings.py` does (the Salsify scenario through `uma.bench.links.link_task`,
seed 0), writes the frame log (`DIR/TRACE-OFFSET-ENGINE.csv`) and the events
(`...-events.txt`), and prints: the row; the display instants whose delay is at or past the
run's p95, gathered into episodes (runs of such instants no more than 1 s apart), each with its
span, its peak delay and, over the 2 s before it, the mean capacity, estimate, sent kbit/s and
the bottleneck queue; and how many of the tail's instants were frozen (a shown picture grown
old) rather than showing a frame that arrived late. Run from the repository root with the
checkout on `PYTHONPATH`.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from links_settings import (
    add_case_arguments,
    case_task,
    cases,
    json_keys,
)  # scripts/, this script's folder


def episodes(times_ms, gap_ms: float = 1000.0) -> list[tuple[float, float, int]]:
    """Runs of instants (sorted ms) no more than `gap_ms` apart: (first, last, count)."""
    out: list[tuple[float, float, int]] = []
    for t in times_ms:
        if out and t - out[-1][1] <= gap_ms:
            first, _, count = out[-1]
            out[-1] = (first, t, count + 1)
        else:
            out.append((t, t, 1))
    return out


def _before(log, first_ms: float, span_ms: float = 2000.0) -> dict:
    import numpy as np

    capture = log["capture_ms"]
    rows = (capture >= first_ms - span_ms) & (capture < first_ms)
    if not rows.any():
        return {}
    sent_bits = float(np.asarray(log["size_bits"])[rows & (log["sent"] > 0)].sum())
    return dict(
        capacity=float(np.nanmean(log["capacity_kbps"][rows])),
        estimate=float(np.nanmean(log["estimate_kbps"][rows])),
        sent=sent_bits / span_ms,
        queue_kb=float(np.mean(log["queue_bytes"][rows])) / 1000.0,
        rung=float(np.mean(log["rung"][rows])),
    )


def _case(job: tuple) -> dict:
    trace, offset_s, duration_s, engine, engine_keys, out_dir = job
    import numpy as np

    from uma.bench.links import row_of
    from uma.config.scenario import Scenario
    from uma.sim import run_scenario
    from uma.sim.summary import run_metrics

    task = case_task(trace, offset_s, duration_s, engine, engine_keys)
    result = run_scenario(Scenario.model_validate(task["scenario"]))
    row = row_of(result, run_metrics(result))
    log = result.log
    stem = f"{Path(trace).stem}-{offset_s:g}-{engine}"
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    Path(out_dir, stem + ".csv").write_text(log.to_csv())
    Path(out_dir, stem + "-events.txt").write_text(
        "\n".join(f"{e.time_s:.3f} {e.kind} {e.detail}" for e in result.events)
    )
    delay = np.asarray(log["delay_ms"])
    finite = np.isfinite(delay)
    p95 = float(np.percentile(delay[finite], 95))
    tail = finite & (delay >= p95)
    display = np.asarray(log["display_ms"])
    eps = []
    for first, last, count in episodes(np.sort(display[tail])):
        rows = tail & (display >= first) & (display <= last)
        eps.append(
            dict(first_s=first / 1000, last_s=last / 1000, instants=count,
                 peak_ms=float(delay[rows].max()), frozen=float(log["frozen"][rows].mean()),
                 before=_before(log, first))
        )  # fmt: skip
    return dict(
        name=stem, row=row, p95=p95, tail=int(tail.sum()),
        tail_frozen=float(log["frozen"][tail].mean()), episodes=eps,
    )  # fmt: skip


def _print(out: dict) -> None:
    row = out["row"]
    print(
        f"{out['name']} p95 {row['delay_p95_ms']:.0f} SSIMu {row['ssim_db_unfrozen']:.2f} "
        f"frozen {row['freeze_ratio']:.4f} util {row['utilisation']:.3f}; tail instants "
        f"{out['tail']} ({out['tail_frozen']:.2f} frozen) in {len(out['episodes'])} episodes"
    )
    for ep in sorted(out["episodes"], key=lambda e: -e["instants"]):
        b = ep["before"]
        ahead = (
            f"cap {b['capacity']:6.0f} est {b['estimate']:6.0f} sent {b['sent']:5.0f} "
            f"queue {b['queue_kb']:6.1f} kB rung {b['rung']:.1f}"
            if b
            else ""
        )
        print(
            f"  {ep['first_s']:7.2f}-{ep['last_s']:7.2f} s n {ep['instants']:4d} peak "
            f"{ep['peak_ms']:6.0f} frozen {ep['frozen']:.2f} | 2 s before: {ahead}"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_case_arguments(parser, "uma,gcc,oracle")
    parser.add_argument("--out", default="/tmp/delay_tail")
    args = parser.parse_args(argv)
    engine_keys = json_keys(args.engine)
    jobs = [(*case, engine_keys, args.out) for case in cases(args)]
    with ProcessPoolExecutor(args.workers) as pool:
        for out in pool.map(_case, jobs):
            _print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
