"""What a viewer sees on GPRS and GSM: uma against H.264 only, split by what is on screen.

`python scripts/mbc_canvas_split.py [SCENARIO.yaml] [--seed N] [--out DIR] [--techs GPRS,GSM]
[--set KEY=JSON ...] [--stretched] [--skip-h264]` runs the scenario as
`uma bench headline`'s `uma` and `h264` engines do (`uma.bench.headline.engine_scenario`),
tags every picture uma's receiver decodes (a full-frame picture by codec and size; a model-
codec picture by the canvas it draws over, its size and age, and by the time since the
refresh taken or since the switch), and prints, per technology, the face PSNR / SSIM of uma's
display instants split by that tag beside H.264 only's at the same instants, and on every 5th
instant the face box's middle half against the rest (the rest again with its light fitted and
with its best shift). It writes OUT_DIR/split.json, uma's per-frame scores
(OUT_DIR/uma_frames.npz) and side-by-side PNGs (source | uma | H.264 only, luma, the face box
drawn) at a few instants of each tag. Run from the repository root; it only watches the
simulation (it patches `ReceiverCoder.decode` in this process and changes nothing it returns).
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import json
from collections import defaultdict
from pathlib import Path

import numpy as np

TECHS = ["GPRS", "GSM"]
STEP = 5  # keep every STEP-th display instant's pictures for the PNGs


def _tagging():
    """Patch the receiver's decode to tag what each decoded frame is; the tags by frame."""
    from uma.codecs import Role, spec
    from uma.sim import coders

    tags: dict[int, str] = {}
    plates: dict[int, np.ndarray] = {}  # the model codec's reference luma, by decoded frame
    state = {"canvas": "none", "age": "", "since": -1, "last": -1}
    original = coders.ReceiverCoder.decode

    def decode(self, unit):
        switched, last = unit.codec != self.codec, state["last"]
        pictures = original(self, unit)
        background = self.context.background
        if pictures:
            state["last"] = max(pictures)
        if switched and background is not None:
            # The canvas is the last picture decoded before the switch (`ReceiverCoder`).
            state["canvas"] = f"{background.shape[1]}x{background.shape[0] * 2 // 3}"
            state["age"] = f" {(unit.frame - last) / self.context.fps:.0f}s old"
            state["since"] = unit.frame
        for frame, picture in pictures.items():
            if spec(unit.codec).role is Role.MODEL:
                taken = getattr(self.decoder, "refresh_frame", -1)
                since = taken if taken >= 0 else state["since"]
                age_s = (frame - since) / self.context.fps
                age = "<2s" if age_s < 2 else ("<6s" if age_s < 6 else ">=6s")
                what = f"refresh {age} old" if taken >= 0 else f"no refresh, switch {age} ago"
                tags[frame] = f"mbc over {state['canvas']}{state['age']}: {what}"
                reference = getattr(getattr(self.decoder, "renderer", None), "reference", None)
                if reference is not None:
                    plates[frame] = reference[: reference.shape[0] * 2 // 3].copy()
            else:
                tags[frame] = f"{unit.codec}@{picture.shape[1]}x{picture.shape[0] * 2 // 3}"
        return pictures

    coders.ReceiverCoder.decode = decode
    return tags, plates, lambda: setattr(coders.ReceiverCoder, "decode", original)


def _luma(picture, width: int, height: int) -> np.ndarray:
    import cv2

    if picture is None:
        return np.full((height, width), 128, np.uint8)
    luma = picture[: picture.shape[0] * 2 // 3]
    if luma.shape != (height, width):
        luma = cv2.resize(luma, (width, height), interpolation=cv2.INTER_LINEAR)
    return np.ascontiguousarray(luma)


def run(scenario, engine: str, keep: set[int] | None):
    """One engine's run: (result, technology per instant, tags or None, kept pictures)."""
    from uma.bench.headline import engine_scenario
    from uma.sim import run_scenario

    variant = engine_scenario(scenario, engine)
    kept: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    size = {}

    def on_display(index, source, shown, picture):
        if keep is None or index in keep:
            h = source.shape[0] * 2 // 3
            size["wh"] = (source.shape[1], h)
            kept[index] = (_luma(source, source.shape[1], h), _luma(picture, source.shape[1], h))

    tags, plates, undo = _tagging() if engine == "uma" else ({}, {}, lambda: None)
    try:
        result = run_scenario(variant, on_display=on_display)
    finally:
        undo()
    from uma.sim.summary import display_technologies, run_metrics

    metrics = run_metrics(result)
    by_tech = metrics["by_technology"]
    print(
        f"{engine}: frozen {metrics['freeze_ratio']} p95 {metrics['delay_p95_ms']} ms; "
        + "; ".join(f"{t} {r['psnr_face_db']} dB / {r['ssim_face']}" for t, r in by_tech.items()),
        flush=True,
    )
    return result, display_technologies(result), tags, kept, plates


def _instant_tag(log, index: int, tags: dict[int, str]) -> str:
    if log["frozen"][index]:
        return "frozen"
    shown = int(log["shown_frame"][index])
    return tags.get(shown, "none shown")


def _ring_fits(source: np.ndarray, shown: np.ndarray, ring: np.ndarray) -> tuple[float, float]:
    """The ring's squared error with the best gain and offset of `shown` (the light), and
    with the best shift of `shown` within 6 px (the pose)."""
    s, u = source[ring].astype(float), shown[ring].astype(float)
    fit = np.linalg.lstsq(np.stack([u, np.ones_like(u)], 1), s, rcond=None)[0]
    light = float(((fit[0] * u + fit[1] - s) ** 2).mean())
    pose = min(
        float(((np.roll(shown, (dy, dx), (0, 1))[ring].astype(float) - s) ** 2).mean())
        for dy in range(-6, 7, 2)
        for dx in range(-6, 7, 2)
    )
    return light, pose


def _parts_db(kept, indices, boxes, plates=None, shown_frames=None) -> dict[str, float | None]:
    """Mean luma PSNR of the kept instants among `indices` over the face box's middle half
    (the face itself) and the rest of the box (hair, neck, body, background); the rest again
    with its light fitted (gain, offset) and with its best shift (`_ring_fits`); with
    `plates`, the rest as the model codec's reference picture shows it, undrawn."""
    errors: dict[str, list[float]] = {
        "inner": [], "ring": [], "ring_lit": [], "ring_moved": [], "plate_ring": []
    }  # fmt: skip
    for index in indices:
        if index not in kept or index >= len(boxes) or boxes[index] is None:
            continue
        source, shown = kept[index]
        box = boxes[index]
        x0, y0, w, h = int(box.x), int(box.y), int(box.width), int(box.height)
        err = (
            source[y0 : y0 + h, x0 : x0 + w].astype(float) - shown[y0 : y0 + h, x0 : x0 + w]
        ) ** 2
        inner = np.zeros(err.shape, bool)
        inner[h // 4 : h - h // 4, w // 4 : w - w // 4] = True
        errors["inner"].append(float(err[inner].mean()))
        errors["ring"].append(float(err[~inner].mean()))
        ring = np.zeros(source.shape, bool)
        ring[y0 : y0 + h, x0 : x0 + w] = ~inner
        lit, moved = _ring_fits(source, shown, ring)
        errors["ring_lit"].append(lit)
        errors["ring_moved"].append(moved)
        plate = None if plates is None else plates.get(int(shown_frames[index]))
        if plate is not None:
            cut = plate[y0 : y0 + h, x0 : x0 + w].astype(float)
            diff = (source[y0 : y0 + h, x0 : x0 + w].astype(float) - cut) ** 2
            errors["plate_ring"].append(float(diff[~inner].mean()))
    return {
        k: round(float(10 * np.log10(255.0**2 / max(np.mean(v), 1e-9))), 2) if v else None
        for k, v in errors.items()
    }


def split(uma, h264, tags) -> dict:
    """Per technology and tag: instants, uma's and H.264 only's mean face PSNR / SSIM there."""
    result, techs = uma[0], uma[1]
    base = h264[0].log
    out: dict = {}
    for tech in TECHS:
        rows: dict[str, list[int]] = defaultdict(list)
        for index in np.flatnonzero(techs == tech):
            rows[_instant_tag(result.log, int(index), tags)].append(int(index))
        table = {}
        for tag, idx in sorted(rows.items(), key=lambda kv: -len(kv[1])):
            idx = np.array(idx)
            table[tag] = {
                "instants": int(idx.size),
                "uma_psnr_face_db": _mean(result.log["psnr_face_db"][idx]),
                "uma_ssim_face": _mean(result.log["ssim_face"][idx]),
                "h264_psnr_face_db": _mean(base["psnr_face_db"][idx]),
                "h264_ssim_face": _mean(base["ssim_face"][idx]),
                "h264_frozen": round(float(base["frozen"][idx].mean()), 3),
                "examples": [int(i) for i in idx[:: max(1, idx.size // 3)][:3]],
                "uma_parts_db": _parts_db(
                    uma[3], idx, result.face_boxes, uma[4], result.log["shown_frame"]
                ),
                "h264_parts_db": _parts_db(h264[3], idx, result.face_boxes),
            }
        out[tech] = table
    return out


def _mean(values) -> float | None:
    values = values[np.isfinite(values)]
    return round(float(values.mean()), 3) if values.size else None


def pngs(out_dir: Path, table: dict, uma_kept, h264_kept, boxes) -> None:
    import cv2

    for tech, rows in table.items():
        for n, row in enumerate(rows.values()):
            for index in row["examples"]:
                index = index - index % STEP
                if index not in uma_kept or index not in h264_kept:
                    continue
                source, shown = uma_kept[index]
                _, base = h264_kept[index]
                strip = np.concatenate([source, shown, base], axis=1)
                strip = cv2.cvtColor(strip, cv2.COLOR_GRAY2BGR)
                box = boxes[index] if index < len(boxes) else None
                if box is not None:
                    w = source.shape[1]
                    for k in range(3):
                        x0 = int(box.x) + k * w
                        cv2.rectangle(strip, (x0, int(box.y)),
                                      (x0 + int(box.width), int(box.y + box.height)), (0, 0, 255), 1)  # fmt: skip
                name = f"{tech}-{n:02d}-{index:05d}.png"
                cv2.imwrite(str(out_dir / name), strip)
                row.setdefault("pngs", []).append(name)


def _changed(scenario, settings: list[str]):
    """`scenario` with each KEY=JSON of `settings` set (dotted keys into its sections)."""
    from uma.config.scenario import Scenario

    if not settings:
        return scenario
    data = scenario.model_dump(mode="json")
    for item in settings:
        key, _, value = item.partition("=")
        *path, last = key.split(".")
        node = data
        for part in path:
            node = node[part]
        node[last] = json.loads(value)
    return Scenario.model_validate(data)


def main(argv: list[str] | None = None) -> int:
    from uma.config.load import load_scenario

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", nargs="?", default="scenarios/stockholm-uppsala.yaml")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", default="/tmp/mbc_canvas_split")
    parser.add_argument("--techs", default=",".join(TECHS), help="technologies to split")
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=JSON",
        help="a scenario key to change (engine.mbc.refresh.min_spare_kbps=2)",
    )
    parser.add_argument(
        "--stretched",
        action="store_true",
        help="the model codec's stretched scene (CodecContext.layered False)",
    )
    parser.add_argument("--skip-h264", action="store_true", help="uma only (no split, no PNGs)")
    args = parser.parse_args(argv)
    TECHS[:] = args.techs.split(",")
    scenario = load_scenario(Path(args.scenario))
    scenario = _changed(scenario.model_copy(update={"seed": args.seed}), args.set)
    if args.stretched:
        import functools

        from uma.sim import codecs

        codecs.CodecContext = functools.partial(codecs.CodecContext, layered=False)
    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    uma = run(scenario, "uma", None)
    log = uma[0].log
    np.savez(out_dir / "uma_frames.npz", **{k: log[k] for k in
             ("codec", "width", "decoded", "shown_frame", "frozen", "psnr_face_db", "ssim_face")},
             technology=uma[1])  # fmt: skip
    if args.skip_h264:
        return 0
    keep = {int(i) for i in np.flatnonzero(np.isin(uma[1], TECHS)) if i % STEP == 0}
    uma_kept = {i: p for i, p in uma[3].items() if i in keep}
    uma = (*uma[:3], uma_kept, uma[4])
    h264 = run(scenario, "h264", keep)
    table = split(uma, h264, uma[2])
    pngs(out_dir, table, uma_kept, h264[3], uma[0].face_boxes)
    for tech, rows in table.items():
        print(
            f"{tech}: tag | instants | uma face PSNR / SSIM | H.264 only face PSNR / SSIM (frozen)"
        )
        for tag, row in rows.items():
            print(
                f"  {tag:48s} {row['instants']:5d}  {row['uma_psnr_face_db']} / "
                f"{row['uma_ssim_face']}  |  {row['h264_psnr_face_db']} / {row['h264_ssim_face']}"
                f" ({row['h264_frozen']})  inner/ring dB uma {row['uma_parts_db']}"
                f" h264 {row['h264_parts_db']}"
            )
    (out_dir / "split.json").write_text(json.dumps(table, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
