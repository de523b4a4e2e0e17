"""The traces the controllers were tuned on, the ones held out, and the closed loop over both.

Units: ms, kbit/s. The split was fixed before any tuning (docs/rate-control.md says why each
trace is where it is): traces of one recording stay on one side (the raw HSDPA log and
Pensieve's cooked bus trace are the same commute), and each side holds slow cellular, outages,
handovers and fast links application-limited at the ladder's top.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["TUNING", "HELD_OUT", "evaluate", "format_loop_table"]

# relative to ../shared/data/traces
TUNING = (
    "mahimahi/TMobile-UMTS-driving.down",
    "mahimahi/Verizon-EVDO-driving.down",
    "pensieve-cooked/bus.ljansbakken-oslo-report.2010-09-28_1407CEST.log",
    "riiser-hsdpa-raw/report.2010-09-28_1407CEST.log",
    "pensieve-cooked/metro.kalbakken-jernbanetorget-report.2011-01-31_2356CET.log",
    "ucc-5g-raca2020/B_2019.12.02_09.39.35.csv",
    "mp-traces-wifi-cellular/7_2_cellular.csv",
    "nyu-mets/bus62.csv",
)
HELD_OUT = (
    "mahimahi/Verizon-LTE-short.down",
    "pensieve-cooked/ferry.nesoddtangen-oslo-report.2010-09-28_1003CEST.log",
    "pensieve-cooked/norway_car_7",
    "pensieve-cooked/trace_10730_http---www.facebook.com",
    "ucc-5g-raca2020/B_2019.12.16_11.49.59.csv",
    "ucc-5g-raca2020/B_2020.02.13_13.03.24.csv",
    "nyu-mets/QTrain.csv",
    "mp-traces-wifi-cellular/7_2_wifi.csv",
    "mp-traces-wifi-cellular/8_5_cellular.csv",
    "mp-traces-wifi-cellular/8_5_wifi.csv",
)
KEYS = ("delay_p95_ms", "delay_median_ms", "utilisation", "sent_over_capacity", "kbps_sent")


def evaluate(
    paths: Iterable[Path],
    settings=None,
    *,
    controllers: Iterable[str] | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Every controller over every trace: per trace and the medians over the traces."""
    from uma.bench.links_loop import CONTROLLERS, run_loop
    from uma.bench.published import trace_name
    from uma.traces import read_trace

    names = tuple(controllers or CONTROLLERS)
    traces: dict[str, Any] = {}
    for path in paths:
        trace = read_trace(path)
        rows = {name: run_loop(trace, name, settings) for name in names}
        traces[trace_name(path)] = {name: {k: row[k] for k in KEYS} for name, row in rows.items()}
        if progress is not None:
            progress(f"loop {trace_name(path)} done")
    median = {}
    for name in names:
        median[name] = {}
        for key in KEYS:
            values = [t[name][key] for t in traces.values() if t[name][key] is not None]
            median[name][key] = round(float(np.median(values)), 4) if values else None
    return {"traces": traces, "median": median}


def format_loop_table(results: dict[str, dict[str, Any]]) -> str:
    """One block per set (tuning, held out): a line per trace and controller, then medians."""
    lines = ["uma bench links --loop: controllers in a pure closed loop (no codec)"]
    head = f"    {'controller':<10}{'p95 ms':>10}{'med ms':>9}{'util':>7}{'sent/c':>8}{'kbit/s':>9}"
    for set_name, result in results.items():
        lines += ["", f"{set_name}"]
        blocks = list(result["traces"].items()) + [("median", result["median"])]
        for trace, rows in blocks:
            lines += [f"  {trace}", head]
            for name, row in rows.items():
                lines.append(
                    f"    {name:<10}{_f(row['delay_p95_ms'], '10,.0f')}"
                    f"{_f(row['delay_median_ms'], '9,.0f')}{_f(row['utilisation'], '7.2f')}"
                    f"{_f(row['sent_over_capacity'], '8.2f')}{_f(row['kbps_sent'], '9.1f')}"
                )
    return "\n".join(lines)


def _f(value, spec: str) -> str:
    return "n/a".rjust(len(format(0.0, spec))) if value is None else format(value, spec)
