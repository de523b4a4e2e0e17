"""docs/targets.md's tables: issues 26 and 27's targets, each judged from bench records.

Each renderer takes the results of the records its block names and returns a table of
target, what the record measured, and the verdict, computed here from the record: a
verdict is never typed. The rules are the issues' words; a rule the README's blocks judge
too (the links rules here, the low-technology face rule in `readme_seeds`) is one function
both call.
"""

from __future__ import annotations

from typing import Any

from readme_seeds import LOW, low_target_met
from readme_seeds import median as _median
from readme_seeds import scenario as _scenario

__all__ = ["TARGET_RENDERERS", "WHOLE_RECORDS", "links_rules"]

Results = list[dict[str, Any]]
Args = dict[str, str]
Row = tuple[str, str, bool]

HEADER = ["| target | measured | verdict |", "|---|---|---|"]


def _verdict(met: bool) -> str:
    return "met" if met else "**not met**"


def _table(rows: list[Row]) -> str:
    return "\n".join(HEADER + [f"| {t} | {m} | {_verdict(ok)} |" for t, m, ok in rows])


def _tech(row: dict[str, Any], tech: str) -> dict[str, Any]:
    return row["by_technology"].get(tech) or {}


def _face(cell: dict[str, Any]) -> str:
    if cell.get("psnr_face_db") is None:
        return "-"
    return f"{cell['psnr_face_db']:.2f} dB / {cell['ssim_face']:.3f}"


def _low_rows(label: str, uma: dict[str, Any], h264: dict[str, Any]) -> list[Row]:
    """Issue 27's face rule in GPRS and GSM: PSNR at least H.264 only's, SSIM at least +0.1."""
    rows = []
    for tech in LOW:
        mine, theirs = _tech(uma, tech), _tech(h264, tech)
        rows.append((
            f"{label}{tech} face: PSNR >= H.264 only's, SSIM >= H.264 only's + 0.1",
            f"{_face(mine)} against {_face(theirs)}",
            low_target_met(mine, theirs, 0.1),
        ))  # fmt: skip
    return rows


def commute_targets(results: Results, args: Args) -> str:
    """Issue 26's default-commute targets on `uma bench headline`'s `uma` row (the first
    record); with `faces=27`, issue 27's GPRS and GSM face targets on the same run instead."""
    rows = _scenario(results[0], args)
    uma, h264 = rows["uma"], rows["h264"]
    if args.get("faces") == "27":
        return _table(_low_rows("", uma, h264))
    gprs, gprs_h264 = _tech(uma, "GPRS"), _tech(h264, "GPRS")
    lag = uma["switch_lag_s"]
    table = [
        ("frozen <= 0.08", f"{uma['freeze_ratio']:.4f}", uma["freeze_ratio"] <= 0.08),
        ("3G frozen <= 0.10", f"{_tech(uma, '3G')['freeze_ratio']:.4f}",
         _tech(uma, "3G")["freeze_ratio"] <= 0.10),
        ("GPRS frozen <= 0.12", f"{gprs['freeze_ratio']:.4f}", gprs["freeze_ratio"] <= 0.12),
        ("delay p95 <= 1,000 ms", f"{uma['delay_p95_ms']:,.0f} ms", uma["delay_p95_ms"] <= 1000),
        ("on the model codec <= 1.0 s after the GPRS handover",
         "never" if lag is None else f"{lag:.2f} s", lag is not None and lag <= 1.0),
        ("GPRS face PSNR at least H.264 only's",
         f"{gprs['psnr_face_db']:.2f} against {gprs_h264['psnr_face_db']:.2f} dB",
         gprs["psnr_face_db"] >= gprs_h264["psnr_face_db"]),
    ]  # fmt: skip
    return _table(table)


def _labels(results: Results, args: Args, key: str) -> list[str]:
    """The records' labels the block gives as `key=` (one each, comma-separated)."""
    labels = args[key].split(",")
    if len(labels) != len(results):
        raise ValueError(f"{key}={args[key]}: {len(results)} records, {len(labels)} labels")
    return labels


def real_targets(results: Results, args: Args) -> str:
    """The real-video commute at every seed (one record each, labelled by `seeds=`): issue
    26's delay and frozen targets, or with `faces=27` issue 27's GPRS and GSM face targets;
    a last `bound.json` record (`bound=1`) adds the link's own p95 for 40-byte packets on the
    same scenario."""
    bound = results[-1] if args.get("bound") == "1" else None
    results = results[:-1] if bound is not None else results
    table: list[Row] = []
    oracle: list[str] = []
    for seed, result in zip(_labels(results, args, "seeds"), results, strict=True):
        rows = _scenario(result, args)
        uma, h264 = rows["uma"], rows["h264"]
        if args.get("faces") == "27":
            table += _low_rows(f"seed {seed}: ", uma, h264)
            continue
        if "oracle" in rows:
            oracle.append(f"seed {seed} {rows['oracle']['delay_p95_ms']:,.0f} ms and "
                          f"{rows['oracle']['freeze_ratio']:.4f}")  # fmt: skip
        p95, theirs = uma["delay_p95_ms"], h264["delay_p95_ms"]
        table += [
            (f"seed {seed}: delay p95 <= 1,500 ms", f"{p95:,.0f} ms", p95 <= 1500),
            (f"seed {seed}: delay p95 below H.264 only's", f"{p95:,.0f} against {theirs:,.0f} ms",
             p95 < theirs),
            (f"seed {seed}: frozen <= 0.15", f"{uma['freeze_ratio']:.4f}",
             uma["freeze_ratio"] <= 0.15),
        ]  # fmt: skip
    out = _table(table)
    if oracle:
        out += ("\n\nThe oracle policy (it reads the link's capacity) on the same runs, delay p95 "
                f"and frozen: {'; '.join(oracle)}.")  # fmt: skip
    if bound is not None:
        name = args.get("scenario") or next(iter(results[0]["scenarios"]))
        scenario = bound["scenarios"][name]
        p95 = scenario["packets"]["40"]["delay_p95_ms"]
        out += (f"\n\nThe link alone (`uma bench bound`: a 40-byte packet sent at each frame's "
                f"capture, nothing else on the link) has a delay p95 of {p95:,.0f} ms on this "
                f"route.")  # fmt: skip
    return out


def links_rules(trace: dict[str, Any]) -> tuple[bool, bool, bool]:
    """Issue 26's three rules on one `uma bench links` trace: uma's p95 at most GCC's, at most
    max(1,000, 1.5 x the oracle's), unfrozen SSIM at most 0.5 dB below GCC's."""
    uma, gcc, oracle = (trace["engines"][name] for name in ("uma", "gcc", "oracle"))
    return (
        uma["delay_p95_ms"] <= gcc["delay_p95_ms"],
        uma["delay_p95_ms"] <= max(1000.0, 1.5 * oracle["delay_p95_ms"]),
        uma["ssim_db_unfrozen"] >= gcc["ssim_db_unfrozen"] - 0.5,
    )


def links_targets(results: Results, args: Args) -> str:
    """`uma bench links` records (labelled by `sets=`): each of issue 26's three rules must
    hold on every trace of a set; the traces that miss are named."""
    names = ("uma's p95 at most GCC's", "uma's p95 at most max(1,000 ms, 1.5 x the oracle's)",
             "uma's unfrozen SSIM at most 0.5 dB below GCC's")  # fmt: skip
    table: list[Row] = []
    for label, result in zip(_labels(results, args, "sets"), results, strict=True):
        traces = result["traces"]
        for index, rule in enumerate(names):
            missed = [name for name, trace in traces.items() if not links_rules(trace)[index]]
            measured = f"{len(traces) - len(missed)} of {len(traces)}"
            if missed:
                measured += f" (not: {', '.join(missed)})"
            table.append((f"{label}: {rule}, on every trace", measured, not missed))
    return _table(table)


def salsify_targets(results: Results, args: Args) -> str:
    """Salsify's TMobile-UMTS setting, whole trace: uma's p95, unfrozen SSIM against
    Salsify-1c's published figure, frozen against the GCC baseline's."""
    result = results[0]
    uma, gcc = result["estimators"]["uma"], result["estimators"]["gcc"]
    published = result["published"]["salsify_1c"]["ssim_db"]
    oracle = result["estimators"].get("oracle")
    return _oracle_line(oracle) + _table([
        ("delay p95 <= 3,000 ms", f"{uma['delay_p95_ms']:,.0f} ms", uma["delay_p95_ms"] <= 3000),
        (f"unfrozen SSIM >= {published:.1f} dB (Salsify-1c, published)",
         f"{uma['ssim_db_unfrozen']:.2f} dB", uma["ssim_db_unfrozen"] >= published),
        ("frozen at most the GCC baseline's",
         f"{uma['freeze_ratio']:.4f} against {gcc['freeze_ratio']:.4f}",
         uma["freeze_ratio"] <= gcc["freeze_ratio"]),
    ])  # fmt: skip


def _oracle_line(oracle: dict[str, Any] | None) -> str:
    """What the oracle policy (it reads the link's capacity) reached on the same run, if run."""
    if oracle is None:
        return ""
    return (f"The oracle policy (it reads the link's capacity) on the same frames: delay p95 "
            f"{oracle['delay_p95_ms']:,.0f} ms, unfrozen SSIM {oracle['ssim_db_unfrozen']:.2f} "
            f"dB, frozen {oracle['freeze_ratio']:.4f}.\n\n")  # fmt: skip


def _pair(cell: dict[str, Any]) -> str:
    return f"{cell['psnr_db']:.2f} / {cell['ssim']:.3f}"


def _mbc_alone(name: str, clip: dict[str, Any]) -> list[Row]:
    face, frame = clip["face"], clip["frame"]
    mbc, h264 = face["quantised"], face["h264_lowest"]
    rate = face["quantised"]["kbps"]
    shown, frozen, h264_frame = frame["quantised"], frame["frozen"], frame["h264_lowest"]
    return [
        (f"{name}: MBC alone at <= 2.5 kbit/s, face PSNR / SSIM >= H.264 16k's",
         f"{_pair(mbc)} ({rate:.2f} kbit/s) against {_pair(h264)}",
         rate <= 2.5 and mbc["psnr_db"] >= h264["psnr_db"] and mbc["ssim"] >= h264["ssim"]),
        (f"{name}: MBC alone, frame SSIM >= the frozen display's and H.264 16k's",
         f"{shown['ssim']:.3f} against {frozen['ssim']:.3f} and {h264_frame['ssim']:.3f}",
         shown["ssim"] >= max(frozen["ssim"], h264_frame["ssim"])),
    ]  # fmt: skip


def _mbc_refresh(name: str, clip: dict[str, Any]) -> list[Row]:
    face, rows = clip["face"], []
    for rung in ("lowest", "second"):
        mine, av1, h264 = (face[f"{kind}_{rung}"] for kind in ("mbc_refresh", "av1", "h264"))
        label = str(clip[f"h264_{rung}"]["rung"]).split()[0]
        rows.append((
            f"{name}: MBC + refresh at the {label} rung's rate, face PSNR >= AV1's at once "
            "and >= H.264's at once + 2 dB",
            f"{mine['psnr_db']:.2f} against {av1['psnr_db']:.2f} and {h264['psnr_db']:.2f} dB",
            mine["psnr_db"] >= max(av1["psnr_db"], h264["psnr_db"] + 2.0),
        ))  # fmt: skip
    return rows


def _tracking(name: str, clip: dict[str, Any]) -> Row:
    frames, reinits, failures = clip["frames"], clip["reinits"], clip["failures"]
    allowed = 2 * frames / 150
    return (
        f"{name}: at most 2 re-initialisations per 150 frames and 5 % of frames without a track",
        f"{reinits} in {frames} frames; {failures} without a track",
        reinits <= allowed and failures <= 0.05 * frames,
    )


def mbc_targets(results: Results, args: Args) -> str:
    """`uma bench mbc`: issue 27's quality and tracking targets per clip (`part=quality` or
    `part=tracking`); the talking head, the model's own rendering, is labelled as such."""
    table: list[Row] = []
    for name, clip in results[0]["clips"].items():
        label = name.replace("-", " ")
        if clip["kind"] != "real clip":
            label += f" ({clip['kind']})"
        if args.get("part") == "tracking":
            table.append(_tracking(label, clip))
        else:
            table += _mbc_alone(label, clip) + _mbc_refresh(label, clip)
    return _table(table)


def speed_targets(records: Results, args: Args) -> str:
    """Issue 27's speed targets, from whole records (`WHOLE_RECORDS`: the wall time is the
    record's, not the bench's), named in this order: the model path per CIF frame (each CIF
    clip's median over the runs of `mbc-speed.json`; the sizes from `mbc.json`), one or more
    `uma bench sim` records' real-time factor, and a whole `uma bench headline --workers 2`."""
    speed, mbc = (record["result"] for record in records[:2])
    limit = float(args.get("limit", "10"))
    table: list[Row] = []
    for name in speed["runs"][0]["clips"]:
        if mbc["clips"][name]["size"] != "352x288":
            continue
        ms = _median([run["clips"][name]["model_path_ms"] for run in speed["runs"]])
        kind = speed["runs"][0]["clips"][name]["kind"]
        label = name.replace("-", " ") + ("" if kind == "real clip" else f" ({kind})")
        runs = len(speed["runs"])
        table.append((f"{label}: model path <= {limit:g} ms a CIF frame (median of {runs} runs)",
                      f"{ms:.2f} ms", ms <= limit))  # fmt: skip
    for sim in (record["result"] for record in records[2:-1]):
        codecs = " and ".join(sim["codecs"])
        table.append((
            f"`{sim['scenario']}` at CIF ({codecs}, {sim['frames']} frames): at least 8x real time",
            f"{sim['realtime_x']:.1f}x", sim["realtime_x"] >= 8.0,
        ))  # fmt: skip
    command, wall_s = records[-1]["command"], records[-1]["duration_s"]
    if "--skip-real" in command or "--scenario" in command:
        raise ValueError(f"{command!r} is not the whole `uma bench headline`")
    table.append(("`uma bench headline --workers 2` under 8 minutes",
                  f"{wall_s:.0f} s", wall_s < 480))  # fmt: skip
    return _table(table)


TARGET_RENDERERS = {
    "targets-commute": commute_targets,
    "targets-real": real_targets,
    "targets-links": links_targets,
    "targets-salsify": salsify_targets,
    "targets-mbc": mbc_targets,
    "targets-speed": speed_targets,
}
# Renderers given the whole records (`command`, `duration_s`, ...), not only their results.
WHOLE_RECORDS = frozenset({"targets-speed"})
