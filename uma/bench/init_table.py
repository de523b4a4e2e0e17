"""The readable output of `uma bench init`: a table like SAABs' Table I, then the summary.

Units: MDE in pixels (RMS distance per model point at 92x112), times in milliseconds.
"""

from __future__ import annotations

from typing import Any

from uma.bench.init import METHOD_NAMES, PAPER_SPLIT, SUCCESS_PX

__all__ = ["format_table"]

_SCOPES = (
    ("all", None),
    ("large pose", "large_pose"),
    ("same light (ORL)", "same_light"),
    ("light change (Yale B)", "light_change"),
    ("light <= 25 deg", "light_within_25deg"),
    ("light > 25 deg", "light_beyond_25deg"),
)
_ROWS = (
    ("median MDE (px)", "mde_median_px"),
    ("p95 MDE (px)", "mde_p95_px"),
    (f"success (MDE < {SUCCESS_PX} px)", "success_rate"),
    ("median time (ms)", "time_median_ms"),
    ("median evaluations", "evaluations_median"),
    ("fits returning a failure", "failures"),
)
_WIDTH = 15


def _fmt(value) -> str:
    if value is None:
        return "n/a"
    return f"{value:.3f}" if isinstance(value, float) else str(value)


def _case_rows(result: dict[str, Any], max_rows: int | None) -> list[str]:
    names = list(METHOD_NAMES)
    if max_rows is None:
        max_rows = len(result["rows"])
    header = f"{'case':<22}{'yaw':>6}{'pitch':>6}{'roll':>6}{'light':>11}{'start':>8}  "
    lines = [header + "".join(f"{n:>{_WIDTH}}" for n in names)]
    for row in result["rows"][:max_rows]:
        mark = "*" if row["large_pose"] else " "
        light = "" if row["light_deg"] is None else row["lighting"]
        cells = "".join(
            f"{row[n]['mde_px']:>{_WIDTH - 1}.3f}{'!' if row[n]['failed'] else ' '}" for n in names
        )
        lines.append(
            f"{row['case'][:21]:<21}{mark}{row['yaw_deg']:>6.1f}{row['pitch_deg']:>6.1f}"
            f"{row['roll_deg']:>6.1f}{light:>11}{row['start_mde_px']:>8.2f}  {cells}"
        )
    if len(result["rows"]) > max_rows:
        lines.append(f"... {len(result['rows']) - max_rows} more cases (see --json)")
    return lines


def format_table(result: dict[str, Any], *, max_rows: int | None = None) -> str:
    """Table I style: one row per case (MDE of each method; all of them unless `max_rows`),
    then the summary by subset."""
    names = list(METHOD_NAMES)
    lines = [
        f"uma bench init: {result['cases']} cases at {result['image']} from "
        f"{len(result['templates'])} templates, seed {result['seed']}; SAABs budget "
        f"{result['evaluation_budget']} cost evaluations (dual_annealing gets the same)",
        f"large pose (*, {result['large_pose_cases']} cases): {result['large_pose_definition']}",
        f"face detector found {result['detector_found']} of {result['cases']} (median "
        f"{_fmt(result['detector_median_ms'])} ms, not in the times below)",
        "MDE: px, RMS over the model points, against the known pose; start: the detector's "
        "proposal; !: the fit returned a failure (counted with its start's error)",
        "light: Yale B light azimuth and elevation (deg); 'light <= 25 deg': its angle from the "
        "camera axis",
        "",
        *_case_rows(result, max_rows),
        "",
        f"{'':<52}" + "".join(f"{n:>{_WIDTH}}" for n in names),
    ]
    for label, key in _ROWS:
        for scope, subset in _SCOPES:
            stats = [
                result["methods"][n] if subset is None else result["methods"][n][subset]
                for n in names
            ]
            count = stats[0]["cases"]
            cells = "".join(f"{_fmt(s[key]):>{_WIDTH}}" for s in stats)
            lines.append(f"{label + ', ' + scope + f' ({count})':<52}{cells}")
    paper = result.get(PAPER_SPLIT)
    if paper:
        lines += [
            "",
            f"SAABs with the paper's split (400 global + 100 local loops, {paper['evaluations_median']} "
            f"evaluations): median {_fmt(paper['time_median_ms'])} ms, MDE median "
            f"{_fmt(paper['mde_median_px'])} px, p95 {_fmt(paper['mde_p95_px'])} px, success "
            f"{_fmt(paper['success_rate'])}",
        ]
    cif = result.get("cif")
    if cif:
        lines += [
            "",
            f"Whole CIF talking-head frames ({cif['frames']} frames, {cif['template_pixels']} "
            "template pixels, detector included; stretch goal: 40 ms a frame)",
        ]
        for method in ("saabs", "hybrid"):
            m = cif[method]
            lines.append(
                f"  {method:<8} median {_fmt(m['time_median_ms'])} ms, MDE median "
                f"{_fmt(m['mde_median_px'])} px, p95 {_fmt(m['mde_p95_px'])} px, "
                f"failures {m['failures']}"
            )
    return "\n".join(lines)
