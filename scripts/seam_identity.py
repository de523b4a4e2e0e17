"""Record or check that a refactor leaves run outputs byte for byte as they were.

`python scripts/seam_identity.py record DIR` runs every scenario of the set below with its seed
fixed and keeps `frames.csv`, `events.csv` and `metrics.json` under `DIR/<name>/`;
`python scripts/seam_identity.py check DIR` runs them again into a temporary folder and compares
each file byte for byte with the recorded one, printing the first differing line and exiting 1
on any difference. Run from the repository root with the checkout on `PYTHONPATH`.

The set: the regression suite's scenarios (VP8 among them), the switching commute cut to 70 s (it
reaches GPRS, so the model-based codec is used), the default commute with the refresh cut to 90 s
(it reaches GSM, so the model codec and its refresh both run), the rate-control commute (pacer,
handover awareness, delay-trend estimator) cut to 70 s, the real-video commute's akiyo on a
short modelled route (a looped file, the face detector, the model codec on real video), and short scenarios that between them use every codec
and path of the engine: face-region rungs with MBC below them (and a failed face search),
the selection scheme, WebRTC's estimator with padding and predictive switching, and oracle
switching, and a switch MBC must refuse (no description). `--only NAME` runs a subset (repeatable).

`--uplink-store` runs each scenario as `uma run` does but through the on-disk store of sender
streams (`uma.experiments.uplink_store`, where `UMA_CACHE` says), as sweeps and benches run:
the first check on an empty store computes and writes every stream (cold), the next takes them
(warm); both must give the recorded bytes. It prints the frames taken and written.
"""

from __future__ import annotations

import argparse
import difflib
import sys
import tempfile
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
FILES = ("frames.csv", "events.csv", "metrics.json")
QCIF_HEAD = {"kind": "talking-head", "width": 176, "height": 144, "fps": 25}

# name -> (scenario file or None, overrides merged on top, seed)
SCENARIOS: dict[str, tuple[str | None, dict, int]] = {
    "short-commute": ("tests/baselines/short-commute.yaml", {}, 3),
    "cell-edge": ("tests/baselines/cell-edge.yaml", {}, 4),
    "talking-head-3g": ("tests/baselines/talking-head-3g.yaml", {}, 5),
    "faults": ("tests/baselines/faults.yaml", {}, 6),
    "switching-70s": ("scenarios/stockholm-uppsala-switching.yaml", {"duration_s": 70.0}, 1),
    "default-refresh-90s": ("scenarios/stockholm-uppsala.yaml", {"duration_s": 90.0}, 1),
    "ratecontrol-70s": ("scenarios/stockholm-uppsala-ratecontrol.yaml", {"duration_s": 70.0}, 1),
    # Real video (akiyo, looped every 300 frames) with the face detector scoring it and the
    # model codec initialised on it (needs ../shared/data).
    "real-akiyo-30s": (
        "scenarios/stockholm-uppsala-real.yaml",
        {
            "duration_s": 30.0,
            "route": [
                {"technology": "3G", "duration_s": 12},
                {"technology": "GPRS", "duration_s": 18},
            ],
        },
        1,
    ),
    "vp8-3g": ("tests/baselines/vp8-3g.yaml", {}, 4),
    "selection": ("scenarios/wlan-gsm-wlan-selection.yaml", {}, 1),
    "face-mbc": (
        None,
        {
            "name": "face-mbc",
            "source": QCIF_HEAD,
            "route": [
                {"technology": "WLAN", "duration_s": 3},
                {"technology": "3G", "duration_s": 3},
                {"technology": "GSM", "duration_s": 4},
                {"technology": "GPRS", "duration_s": 5},
                {"technology": "GSM", "duration_s": 5},
                {"technology": "3G", "duration_s": 5},
            ],
            "engine": {
                "switching": {"policy": "threshold", "min_dwell_ms": 1000, "retry_ms": 2000},
                "face_region": {"enabled": True},
            },
            "receiver": {"playout": "adaptive"},
        },
        7,
    ),
    "face-oracle": (
        None,
        {
            "name": "face-oracle",
            "source": QCIF_HEAD,
            "route": [
                {"technology": "WLAN", "duration_s": 2},
                {"technology": "GSM", "duration_s": 5},
                {"technology": "WLAN", "duration_s": 4},
            ],
            "engine": {"policy": "oracle", "face_region": {"enabled": True}},
            "receiver": {"playout_delay_ms": 800},
        },
        1,
    ),
    "face-none-found": (
        None,
        {
            "name": "face-none-found",
            "source": {"kind": "pattern", "width": 176, "height": 144, "fps": 25},
            "route": [
                {"technology": "WLAN", "duration_s": 2},
                {"technology": "GSM", "duration_s": 5},
                {"technology": "WLAN", "duration_s": 3},
            ],
            "engine": {"policy": "oracle", "face_region": {"enabled": True}},
            "metrics": {"ssim": False},
        },
        2,
    ),
    "webrtc-predictive": (
        None,
        {
            "name": "webrtc-predictive",
            "source": QCIF_HEAD,
            "route": [
                {"technology": "3G", "duration_s": 5},
                {"technology": "GPRS", "duration_s": 6},
                {"technology": "3G", "duration_s": 5},
            ],
            "engine": {
                "estimator": "webrtc",
                "switching": {"policy": "predictive", "lookahead_ms": 1000, "min_dwell_ms": 500},
            },
        },
        8,
    ),
    "mbc-refused": (
        None,
        {
            "name": "mbc-refused",
            "source": {"kind": "pattern", "width": 176, "height": 144, "fps": 25},
            "route": [
                {"technology": "3G", "duration_s": 3},
                {"technology": "GSM", "duration_s": 5},
            ],
            "engine": {"switching": {"policy": "threshold", "min_dwell_ms": 500}},
            "metrics": {"ssim": False},
        },
        10,
    ),
    "oracle-switching": (
        None,
        {
            "name": "oracle-switching",
            "source": QCIF_HEAD,
            "route": [
                {"technology": "WLAN", "duration_s": 3},
                {"technology": "GSM", "duration_s": 6},
                {"technology": "EDGE", "duration_s": 3},
                {"technology": "WLAN", "duration_s": 3},
            ],
            "engine": {"policy": "oracle", "switching": {"policy": "oracle"}},
            "metrics": {"ssim": False},
        },
        9,
    ),
}


def _merge(base: dict, over: dict) -> dict:
    out = dict(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = value
    return out


def _scenario_file(name: str, work: Path) -> Path:
    """The scenario to run: the file itself, or a copy with the overrides beside it."""
    path, over, _ = SCENARIOS[name]
    if path is not None and not over:
        return ROOT / path
    data = yaml.safe_load((ROOT / path).read_text()) if path else {}
    data = _merge(data, over)
    folder = (ROOT / path).parent if path else work
    out = Path(tempfile.mkstemp(prefix=f".{name}-", suffix=".yaml", dir=folder)[1])
    out.write_text(yaml.safe_dump(data, sort_keys=False))
    return out


def _run_through_store(path: Path, out: Path, seed: int) -> str:
    """`uma run PATH --seed SEED --out OUT` through the store of sender streams."""
    from uma.config import load_scenario
    from uma.experiments.uplink_store import UplinkStore, store_settings
    from uma.sim import run_scenario
    from uma.sim.summary import save_run

    settings = store_settings()
    if settings is None:
        raise SystemExit("--uplink-store: UMA_CACHE=off turns the store off; expected it on")
    store = UplinkStore(settings)
    save_run(run_scenario(load_scenario(path).with_seed(seed), uplink=store), out)
    return f" (store: {store.hits} frames taken, {store.written} written)"


def run(name: str, out: Path, work: Path, *, store: bool = False) -> str:
    from uma.cli import main

    path = _scenario_file(name, work)
    note = ""
    try:
        seed = SCENARIOS[name][2]
        if store:
            note, status = _run_through_store(path, out, seed), 0
        else:
            status = main(["run", str(path), "--out", str(out), "--seed", str(seed), "--quiet"])
    finally:
        if path.name.startswith("."):
            path.unlink()
    if status != 0:
        raise SystemExit(f"{name}: uma run exited {status}")
    return note


def _first_difference(a: bytes, b: bytes) -> str:
    lines = difflib.unified_diff(
        a.decode().splitlines(), b.decode().splitlines(), "before", "after", n=0, lineterm=""
    )
    return "\n".join(list(lines)[:8])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mode", choices=("record", "check"))
    parser.add_argument("dir", type=Path)
    parser.add_argument("--only", action="append", choices=sorted(SCENARIOS))
    parser.add_argument("--uplink-store", action="store_true", help="run through the store")
    args = parser.parse_args(argv)
    names = args.only or list(SCENARIOS)
    bad = 0
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for name in names:
            target = args.dir / name if args.mode == "record" else work / name
            note = run(name, target, work, store=args.uplink_store)
            if args.mode == "record":
                print(f"{name}: recorded{note}")
                continue
            if note:
                print(f"{name}:{note}")
            for file in FILES:
                before = (args.dir / name / file).read_bytes()
                after = (target / file).read_bytes()
                if before != after:
                    bad += 1
                    print(f"{name}/{file}: DIFFERS\n{_first_difference(before, after)}")
                else:
                    print(f"{name}/{file}: identical ({len(after)} bytes)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
