"""Why each frozen display instant of `uma bench links`'s scenario is frozen, per engine.

`python scripts/freeze_causes.py --case TRACE:OFFSET_S:DURATION_S [--case ...] [--engines
uma,gcc,oracle] [--engine KEY=JSON ...] [--workers 2] [--json OUT]` runs each case and engine
as `scripts/links_settings.py` does (the Salsify scenario through `uma.bench.links.link_task`,
seed 0) and sorts every frozen instant by the cause its frame met. The frame an instant is
owed is the last one the rung's frame rate scheduled (`uma.sim.playout_replay.DisplayRule`);
it was:

- `skip`: not coded by the rate control's skip rule with a report in hand (the queue budget),
  `skip_paused`: not coded while the controller was paused (no report for its `pause_ms`);
- `backlog`: held by the pacing backlog rule (`uma.engine.pacing.held`);
- `not_coded`: scheduled and not skipped, and the coder sent nothing (a failure);
- `pacer_drop`: coded, then dropped by the pacer as too late to be shown;
- `lost`: sent, and its unit never complete at the receiver (a packet dropped by the link);
- `kf_wait`: complete at the receiver but undecodable (a broken chain waiting for a keyframe);
- `late_key`, `late`: decoded after the instant; the frame a keyframe (a new size, a
  request), or a P-frame;
- `start`: no frame scheduled and shown yet.

Also per engine: frames coded per second, keyframes, skipped frames, pacer drops. The engine's
decision and the receiver's completion are observed by wrapping their methods in the worker
process (nothing changes what the run does: its row is the bench's). Run from the repository
root with the checkout on `PYTHONPATH`.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import json
import re
import sys
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from links_settings import (
    add_case_arguments,
    case_task,
    cases,
    json_keys,
)  # scripts/, this script's folder

CAUSES = (
    "skip", "skip_paused", "backlog", "not_coded", "pacer_drop", "lost", "kf_wait",
    "late_key", "late", "start",
)  # fmt: skip


def _observe():
    """Wrap the engine's send decision and the receiver's completion; what they saw."""
    from uma.engine.engine import UmaEngine
    from uma.sim.receiver import ReceiverState

    seen = {"reason": {}, "complete": {}, "broken_units": set()}
    send_or_hold = UmaEngine._send_or_hold

    def _send_or_hold(self, decision, now_s, *args):
        out = send_or_hold(self, decision, now_s, *args)
        reason = out.reason if not out.send else "send"
        if reason == "skip" and self.rate.paused(now_s):
            reason = "skip_paused"
        seen["reason"][decision.frame] = reason
        return out

    complete = ReceiverState._complete

    def _complete(self, unit, now_s):
        frames = getattr(unit, "frames", None) or (unit.frame,)
        for frame in frames:
            seen["complete"][frame] = now_s * 1000.0
        return complete(self, unit, now_s)

    UmaEngine._send_or_hold = _send_or_hold
    ReceiverState._complete = _complete
    return seen


def _dropped(events) -> set[int]:
    frames: set[int] = set()
    for event in events:
        if event.kind == "pacer_drop":
            first, last = map(int, re.match(r"frames (\d+)-(\d+)", event.detail).groups())
            frames.update(range(first, last + 1))
    return frames


def classify(log, seen: dict, dropped: set[int]) -> Counter:
    """Per cause, the frozen instants of the run's frame log."""
    import numpy as np

    scheduled, frozen = np.asarray(log["scheduled"]), np.asarray(log["frozen"])
    sent, key = np.asarray(log["sent"]), np.asarray(log["keyframe"])
    arrival, display = np.asarray(log["arrival_ms"]), np.asarray(log["display_ms"])
    shown = np.asarray(log["shown_frame"])
    causes: Counter = Counter()
    owed = -1
    for index in range(len(frozen)):
        if scheduled[index]:
            owed = index
        if not frozen[index]:
            continue
        reason = seen["reason"].get(owed, "")
        if owed < 0 or shown[index] < 0:
            cause = "start"
        elif reason in ("skip", "skip_paused", "backlog"):
            cause = reason
        elif not sent[owed]:
            cause = "not_coded"
        elif owed in dropped:
            cause = "pacer_drop"
        elif np.isfinite(arrival[owed]) and arrival[owed] > display[index]:
            cause = "late_key" if key[owed] else "late"
        elif owed in seen["complete"]:
            cause = "kf_wait"
        else:
            cause = "lost"
        causes[cause] += 1
    return causes


def _case(job: tuple) -> dict:
    trace, offset_s, duration_s, engine, engine_keys = job
    import numpy as np

    seen = _observe()
    from uma.bench.links import row_of
    from uma.config.scenario import Scenario
    from uma.sim import run_scenario
    from uma.sim.summary import run_metrics

    task = case_task(trace, offset_s, duration_s, engine, engine_keys)
    result = run_scenario(Scenario.model_validate(task["scenario"]))
    row = row_of(result, run_metrics(result))
    dropped = _dropped(result.events)
    causes = classify(result.log, seen, dropped)
    log = result.log
    sent = np.asarray(log["sent"]).astype(bool)
    reasons = Counter(seen["reason"].values())
    return dict(
        trace=Path(trace).stem, offset_s=offset_s, duration_s=duration_s, engine=engine,
        row=row, instants=int(log.frames), causes=dict(causes),
        coded_per_s=round(float(sent.sum()) / duration_s, 2),
        keyframes=int((np.asarray(log["keyframe"]) > 0).sum()),
        decisions=dict(reasons), pacer_dropped=len(dropped),
    )  # fmt: skip


def _print(out: dict) -> None:
    total = out["instants"]
    row = out["row"]
    print(
        f"{out['trace'][:22]:22s} {out['offset_s']:4.0f}+{out['duration_s']:3.0f} "
        f"{out['engine']:6s} p95 {row['delay_p95_ms']:7.0f} SSIMu {row['ssim_db_unfrozen']:5.2f} "
        f"frozen {row['freeze_ratio']:.4f} util {row['utilisation']:.3f} "
        f"coded/s {out['coded_per_s']:5.2f} keyframes {out['keyframes']} "
        f"pacer drops {out['pacer_dropped']} decisions {out['decisions']}"
    )
    print("   " + "  ".join(f"{c} {out['causes'].get(c, 0) / total:.4f}" for c in CAUSES))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_case_arguments(parser, "uma,gcc,oracle")
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    engine_keys = json_keys(args.engine)
    jobs = [(*case, engine_keys) for case in cases(args)]
    outs = []
    with ProcessPoolExecutor(args.workers) as pool:
        for out in pool.map(_case, jobs):
            _print(out)
            outs.append(out)
    if args.json:
        Path(args.json).write_text(json.dumps({"engine": engine_keys, "runs": outs}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
