"""`uma bench face-rung`: choose and quote the face-region H.264 rung's settings on real clips."""

from __future__ import annotations

import argparse

__all__ = ["register"]


def register(sub: argparse._SubParsersAction) -> None:
    from uma.cli.cmd_bench import add_common_arguments

    parser = sub.add_parser(
        "face-rung",
        help="the face-region H.264 rung on real clips: settings grid, quote, whole runs, cost",
        description="--grid CLIP codes a clip at every candidate face-region setting and scores "
        "the receiver's composite over the source's face box against the lowest full-frame "
        "rung; --quote CLIP does so for the default (or --rung) settings; --run CLIP simulates a "
        "WLAN-then-GSM route three ways (H.264 only, with the face rungs, switching to MBC); "
        "--cost measures the detector's CPU time per scanned pixel. CLIP is akiyo, carphone or "
        "a video file. Prints one JSON object.",
    )
    parser.add_argument("--grid", metavar="CLIP", help="choose settings on CLIP")
    parser.add_argument("--quote", metavar="CLIP", help="the default rungs on CLIP")
    parser.add_argument("--run", metavar="CLIP", help="whole runs, three engines, on CLIP")
    parser.add_argument("--cost", action="store_true", help="the detector's CPU cost")
    parser.add_argument("--frames", type=int, default=150, help="clip frames (default 150)")
    parser.add_argument(
        "--rung", action="append", metavar="RATE:WxH@FPS", help="face rungs for --quote, --run"
    )
    parser.add_argument("--no-mbc", action="store_true", help="--run without the MBC engine")
    parser.add_argument("--max-backlog-ms", type=float, help="engine.max_backlog_ms for --run")
    parser.add_argument("--policy", default="oracle", help="engine.policy for --run")
    parser.add_argument("--gsm-s", type=float, default=16.0, help="GSM seconds for --run")
    add_common_arguments(parser)
    parser.set_defaults(func=handle)


def _check_clip(option: str, name: str | None) -> None:
    from pathlib import Path

    from uma.bench.face_rung import CLIPS
    from uma.errors import ConfigError

    if name is not None and name not in CLIPS and not Path(name).is_file():
        raise ConfigError(
            f"{option}: expected {', '.join(sorted(CLIPS))} or a video file, got {name!r}"
        )


def handle(args: argparse.Namespace) -> int:
    import json
    import sys
    from typing import Any

    from uma.errors import ConfigError

    if args.frames <= 0:
        raise ConfigError(f"--frames: expected a positive integer, got {args.frames}")
    if not (args.grid or args.quote or args.run or args.cost):
        raise ConfigError("expected at least one of --grid, --quote, --run, --cost")
    for option in ("grid", "quote", "run"):
        _check_clip(f"--{option}", getattr(args, option))
    from uma.bench.face_rung import face_config, grid, quote
    from uma.bench.face_rung_run import detector_cost, run_three_ways

    face_config(args.rung)  # a bad --rung is exit 2 before any work
    result: dict[str, Any] = {}
    if args.grid:
        result["grid"] = grid(args.grid, args.frames)
    if args.quote:
        result["quote"] = quote(args.quote, args.frames, args.rung)
    if args.run:
        result["run"] = run_three_ways(
            args.run,
            rungs=args.rung,
            model=not args.no_mbc,
            max_backlog_ms=args.max_backlog_ms,
            policy=args.policy,
            gsm_s=args.gsm_s,
        )
    if args.cost:
        result["cost"] = detector_cost(min(args.frames, 60))
    json.dump(result, sys.stdout, indent=None if args.json else 1)
    sys.stdout.write("\n")
    return 0
