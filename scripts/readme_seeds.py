"""Generated blocks over one `uma bench headline` scenario recorded at several seeds, and the
helpers the other renderers (scripts/readme_blocks.py) share: a record's scenario rows, the
median, and the low technologies' face target.

A block names its records in seed order and labels them with `seeds=1,2,...`; `engine=`
(default uma) is judged against `base=` (default h264).
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "LOW",
    "headline_seeds",
    "headline_seeds_faces",
    "headline_seeds_verdict",
    "low_target_met",
    "median",
    "scenario",
]

Results = list[dict[str, Any]]
Args = dict[str, str]
LOW = ("GPRS", "GSM")


def scenario(result: dict[str, Any], args: Args) -> dict[str, Any]:
    """The rows (engine -> row) of the record's scenario named `scenario=`, else its first."""
    name = args.get("scenario") or next(iter(result["scenarios"]))
    return result["scenarios"][name]


def median(values: list[float]) -> float:
    ordered = sorted(values)
    middle = len(ordered) // 2
    return ordered[middle] if len(ordered) % 2 else (ordered[middle - 1] + ordered[middle]) / 2


def low_target_met(mine: dict[str, Any], theirs: dict[str, Any], ssim_margin: float) -> bool:
    """Issue 27's face target in one technology: face PSNR at least the base's and face SSIM at
    least the base's + `ssim_margin`; False when either side lacks a figure."""
    figures = (
        mine.get("psnr_face_db"),
        theirs.get("psnr_face_db"),
        mine.get("ssim_face"),
        theirs.get("ssim_face"),
    )
    if None in figures:
        return False
    psnr_a, psnr_b, ssim_a, ssim_b = figures
    return psnr_a >= psnr_b and ssim_a >= ssim_b + ssim_margin


def _seed_rows(results: Results, args: Args) -> list[tuple[str, dict[str, Any], dict[str, Any]]]:
    """(seed label, engine row, base row) per record; `seeds=` labels the records in order."""
    seeds = args["seeds"].split(",")
    if len(seeds) != len(results):
        raise ValueError(f"seeds={args['seeds']}: {len(results)} records, {len(seeds)} labels")
    engine, base = args.get("engine", "uma"), args.get("base", "h264")
    rows = [scenario(result, args) for result in results]
    return [(seed, row[engine], row[base]) for seed, row in zip(seeds, rows, strict=True)]


def headline_seeds(results: Results, args: Args) -> str:
    """One scenario of `uma bench headline` at several seeds: p95 and frozen, engine and base."""
    rows = _seed_rows(results, args)
    engine, base = args.get("engine", "uma"), args.get("base", "h264")
    lines = [
        f"| seed | {engine} p95 ms | {base} p95 ms | {engine} frozen | {base} frozen |",
        "|---|---|---|---|---|",
    ]
    for seed, mine, theirs in rows:
        lines.append(
            f"| {seed} | {mine['delay_p95_ms']:,.0f} | {theirs['delay_p95_ms']:,.0f} "
            f"| {mine['freeze_ratio']:.3f} | {theirs['freeze_ratio']:.3f} |"
        )
    medians = [
        median([row[i][key] for row in rows])
        for key in ("delay_p95_ms", "freeze_ratio")
        for i in (1, 2)
    ]
    lines.append(
        f"| median | {medians[0]:,.0f} | {medians[1]:,.0f} | {medians[2]:.3f} | {medians[3]:.3f} |"
    )
    return "\n".join(lines)


def headline_seeds_verdict(results: Results, args: Args) -> str:
    """How many seeds meet the real commute's rules: p95 below the base's, frozen <= `frozen=`."""
    rows = _seed_rows(results, args)
    limit = float(args.get("frozen", "0.15"))
    below = sum(mine["delay_p95_ms"] < theirs["delay_p95_ms"] for _, mine, theirs in rows)
    calm = sum(mine["freeze_ratio"] <= limit for _, mine, _ in rows)
    p95 = median([mine["delay_p95_ms"] for _, mine, _ in rows])
    base_p95 = median([theirs["delay_p95_ms"] for _, _, theirs in rows])
    frozen = median([mine["freeze_ratio"] for _, mine, _ in rows])
    return (
        f"over seeds {args['seeds']}, uma's p95 is below H.264 only's on {below} of {len(rows)} "
        f"(medians {p95:,.0f} against {base_p95:,.0f} ms) and its frozen share at most "
        f"{limit:g} on {calm} of {len(rows)} (median {frozen:.3f})"
    )


def _face(cell: dict[str, Any] | None) -> str:
    return "-" if cell is None else f"{cell['psnr_face_db']:.2f} / {cell['ssim_face']:.3f}"


def headline_seeds_faces(results: Results, args: Args) -> str:
    """Issue 27's GPRS and GSM face target at each seed (`ssim_margin=`, default 0.1): face
    PSNR dB / SSIM of the engine and the base, which technologies meet it, and a count."""
    rows = _seed_rows(results, args)
    margin = float(args.get("ssim_margin", "0.1"))
    engine, base = args.get("engine", "uma"), args.get("base", "h264")
    lines = [
        "| seed | "
        + " | ".join(f"{tech} face {engine} | {tech} face {base}" for tech in LOW)
        + " | met in |",
        "|---|" + "---|" * (2 * len(LOW) + 1),
    ]
    counts = dict.fromkeys(LOW, 0)
    for seed, mine, theirs in rows:
        cells, met = [], []
        for tech in LOW:
            a, b = mine["by_technology"].get(tech), theirs["by_technology"].get(tech)
            cells += [_face(a), _face(b)]
            if a is not None and b is not None and low_target_met(a, b, margin):
                met.append(tech)
                counts[tech] += 1
        said = " and ".join(met) if met else "**neither**"
        lines.append(f"| {seed} | " + " | ".join(cells) + f" | {said} |")
    tally = ", ".join(f"{tech} on {counts[tech]} of {len(rows)}" for tech in LOW)
    lines += [
        "",
        f"Face PSNR at least {base}'s and face SSIM at least {margin:g} above it: {tally}.",
    ]
    return "\n".join(lines)
