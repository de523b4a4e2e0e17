"""`uma report RESULTS_DIR`: the timeline PNG of a run (and its receiver video), or a sweep's plot."""

from __future__ import annotations

import argparse

__all__ = ["register"]

HELP = """\
For a run's results folder (what `uma run` writes): draw timeline.png (capacity over
technology bands, the engine's estimate, bit rate per codec, displayed PSNR, freezes, rung
switches, handovers, keyframe requests). With --video, also receiver.mp4: what the receiver
displayed beside the source, with codec, rate and technology in a corner (the run is simulated
again from its scenario.yaml, which repeats it exactly).

For a sweep's folder (it holds sweep.csv): draw summary-<metric>.png, --metric against the grid
key --x, one line per combination of the other grid keys, seeds averaged; failed points and
points not run yet (status missing: the sweep is incomplete) are counted in the title.
Exit status: 0 done, 2 bad input (no results there, a damaged file: one line naming its line,
unknown metric or key)."""


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "report",
        help="draw a run's timeline (and --video) or a sweep's summary plot",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("results", metavar="RESULTS_DIR", help="a run's or a sweep's folder")
    parser.add_argument("--video", action="store_true", help="also write receiver.mp4 (a run)")
    parser.add_argument("--metric", default="freeze_ratio", help="sweep plot: the metric (y)")
    parser.add_argument("--x", metavar="KEY", help="sweep plot: the grid key on the x axis")
    parser.add_argument("--out", metavar="FILE", help="the picture's path (default in the folder)")
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from uma.errors import ConfigError

    folder = Path(args.results)
    if (folder / "sweep.csv").is_file():
        from uma.report.sweep_plot import draw_sweep_summary

        if args.video:
            raise ConfigError(
                f"--video: {folder} is a sweep; give one run's folder (points/<hash>)"
            )
        print(draw_sweep_summary(folder, args.out, metric=args.metric, x=args.x))
        return 0
    from uma.report.timeline import draw_timeline

    print(draw_timeline(folder, args.out))
    if args.video:
        from uma.report.video import write_receiver_video

        print(write_receiver_video(folder))
    return 0
