"""The real commute's settings on one stretch of one trace, with engine keys changed.

`python scripts/real_stretch.py TRACE OFFSET_S DURATION_S OUT_DIR [--engine KEY=JSON ...]
[--seed N]` writes a one-segment scenario (3G, akiyo looped, threshold switching to the model
codec, adaptive playout: scenarios/stockholm-uppsala-real.yaml's engine and receiver) to
OUT_DIR/scenario-in.yaml and runs `uma run` on it into OUT_DIR/run. `--engine` merges into the
scenario's `engine` section (`switching={"policy":"threshold","calm_ms":5000}`). The links
bench (`scripts/links_settings.py`) codes H.264 only, where the switching keys do nothing
(docs/rate-control.md, branch rc25). Run from the repository root.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent


def scenario(trace: str, offset_s: float, duration_s: float, engine: dict) -> dict:
    """The real commute's scenario cut to one 3G segment of `trace` from `offset_s`."""
    real = yaml.safe_load((ROOT / "scenarios/stockholm-uppsala-real.yaml").read_text())
    shared = (ROOT / "../shared/data").resolve()
    real["name"] = f"{Path(trace).stem}-{offset_s:g}"
    real["source"]["path"] = str(shared / "faces/video/akiyo.mp4")
    real["route"] = [dict(technology="3G", duration_s=duration_s, trace=str(Path(trace).resolve()),
                          offset_s=offset_s)]  # fmt: skip
    real["engine"]["mbc"]["description"] = str(ROOT / "codecs/face/akiyo.yaml")
    for key, value in engine.items():
        real["engine"][key] = value
    return real


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trace")
    parser.add_argument("offset_s", type=float)
    parser.add_argument("duration_s", type=float)
    parser.add_argument("out")
    parser.add_argument("--engine", action="append", default=[], help="engine KEY=JSON")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    engine = {}
    for item in args.engine:
        key, _, value = item.partition("=")
        engine[key] = json.loads(value)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "scenario-in.yaml"
    path.write_text(yaml.safe_dump(scenario(args.trace, args.offset_s, args.duration_s, engine)))
    command = [sys.executable, "-m", "uma", "run", str(path), "--seed", str(args.seed),
               "--quiet", "--out", str(out / "run")]  # fmt: skip
    return subprocess.call(command)


if __name__ == "__main__":
    sys.exit(main())
